#include "sim/io/toml.h"

#include "plugin/base/error.h"

namespace ipmc {

toml::table ParseToml(const std::string& text, const std::string& source) {
  try {
    return toml::parse(text, source);
  } catch (const toml::parse_error& error) {
    const toml::source_position& where = error.source().begin;
    throw InputError(InputProblem::kSyntax, {source, where.line, where.column}, "",
                     std::string(error.description()));
  }
}

}  // namespace ipmc
