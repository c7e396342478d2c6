#include "sim/io/toml.h"

#include <cstdint>

#include "sim/base/error.h"

namespace ipmc {
namespace {

// The deepest key path (dotted key or table header) a document may hold:
// toml++ limits inline tables and arrays (TOML_MAX_NESTED_VALUES) but not
// these, and a table nested many thousands deep overflows the stack when
// it is built or destroyed. The program's own keys are at most 3 deep.
constexpr int kMaxKeyDepth = 32;

// Throws InputError (kSyntax) "SOURCE:LINE: a key nested more than N
// levels deep (...)" for the first key path deeper than kMaxKeyDepth.
// Outside strings and comments, the dots of a key path come one after
// another with nothing but key names between them; a value holds at most
// one dot in a row (1.5, 07:32:00.999), so every run of dots that '=',
// a bracket, a brace, a comma or a line end does not break is a key path.
void RequireShallowKeys(const std::string& text, const std::string& source) {
  std::uint32_t line = 1;
  int dots = 0;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '"' || c == '\'') {
      // A string, with escapes in "..."; multi-line ("""...""") too.
      const bool triple = text.compare(i, 3, std::string(3, c)) == 0;
      const std::string end = triple ? std::string(3, c) : std::string(1, c);
      size_t j = i + end.size();
      for (; j < text.size() && text.compare(j, end.size(), end) != 0; ++j) {
        if (text[j] == '\\' && c == '"') ++j;
        else if (text[j] == '\n') ++line;
      }
      i = j + end.size() - 1;
    } else if (c == '#') {
      while (i + 1 < text.size() && text[i + 1] != '\n') ++i;
    } else if (c == '.') {
      if (++dots >= kMaxKeyDepth) {
        throw InputError(InputProblem::kSyntax, {source, line}, "",
                         "a key nested more than " + std::to_string(kMaxKeyDepth) +
                             " levels deep (a dotted key or table header of at most " +
                             std::to_string(kMaxKeyDepth) + " parts)");
      }
    } else if (c == '=' || c == '[' || c == ']' || c == '{' || c == '}' || c == ',' ||
               c == '\n') {
      dots = 0;
      if (c == '\n') ++line;
    }
  }
}

// Throws InputError (kBadValue) "SOURCE:LINE: KEY: a string with a NUL
// byte (...)" for the first string value (at any depth) holding one: any
// string may be a path (a scenario's model, a sweep's base), which the
// system would end at the NUL and so name another file.
void RequireNoNulStrings(const toml::node& node, const std::string& key,
                         const std::string& source) {
  if (const toml::value<std::string>* text = node.as_string()) {
    if (text->get().find('\0') == std::string::npos) return;
    throw InputError(InputProblem::kBadValue, {source, node.source().begin.line}, key,
                     key + ": a string with a NUL byte (a path would end there)",
                     "strings without NUL bytes");
  }
  if (const toml::table* table = node.as_table()) {
    for (auto&& [name, value] : *table) {
      RequireNoNulStrings(value, key.empty() ? std::string(name.str())
                                             : key + "." + std::string(name.str()),
                          source);
    }
  } else if (const toml::array* array = node.as_array()) {
    for (std::size_t i = 0; i < array->size(); ++i) {
      RequireNoNulStrings(*array->get(i), key + "[" + std::to_string(i) + "]", source);
    }
  }
}

}  // namespace

toml::table ParseToml(const std::string& text, const std::string& source) {
  RequireShallowKeys(text, source);
  try {
    toml::table table = toml::parse(text, source);
    RequireNoNulStrings(table, "", source);
    return table;
  } catch (const toml::parse_error& error) {
    const toml::source_position& where = error.source().begin;
    throw InputError(InputProblem::kSyntax, {source, where.line, where.column}, "",
                     std::string(error.description()));
  }
}

}  // namespace ipmc
