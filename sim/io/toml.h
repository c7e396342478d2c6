// TOML documents: parsing with one-line errors, and the names of value
// types for messages.
#pragma once

#include <toml++/toml.h>

#include <string>

namespace ipmc {

// Parses `text`; a syntax error throws InputError (sim/base/error.h,
// problem kSyntax) "SOURCE:LINE:COLUMN: description" on one line, a
// string value with a NUL byte (which a path would end at) InputError
// (kBadValue) "SOURCE:LINE: KEY: a string with a NUL byte (...)".
toml::table ParseToml(const std::string& text, const std::string& source);

inline std::string TomlTypeName(toml::node_type type) {
  switch (type) {
    case toml::node_type::string:
      return "string";
    case toml::node_type::integer:
      return "integer";
    case toml::node_type::floating_point:
      return "float";
    case toml::node_type::boolean:
      return "boolean";
    case toml::node_type::array:
      return "array";
    case toml::node_type::table:
      return "table";
    case toml::node_type::date:
      return "date";
    case toml::node_type::time:
      return "time";
    case toml::node_type::date_time:
      return "date-time";
    case toml::node_type::none:
      break;
  }
  return "nothing";
}

}  // namespace ipmc
