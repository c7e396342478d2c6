#include "sim/base/error.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "sim/base/numbers.h"

namespace ipmc {
namespace {

std::string Located(const InputLocation& where, const std::string& message) {
  std::string text = where.file;
  if (where.line > 0) text += ":" + std::to_string(where.line);
  if (where.line > 0 && where.column > 0) text += ":" + std::to_string(where.column);
  return OneLine(text + ": " + message);
}

}  // namespace

std::string OneLine(std::string text) {
  std::replace_if(
      text.begin(), text.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
  return text;
}

InputError::InputError(InputProblem problem, InputLocation where, std::string key,
                       std::string message, std::string allowed)
    : std::runtime_error(Located(where, message)),
      problem_(problem),
      where_(std::move(where)),
      key_(std::move(key)),
      message_(OneLine(std::move(message))),
      allowed_(std::move(allowed)) {}

FieldError::FieldError(const std::string& message, std::string field, std::string allowed)
    : std::invalid_argument(message), field_(std::move(field)), allowed_(std::move(allowed)) {}

void ThrowOption(const std::string& who, const std::string& option, const std::string& allowed,
                 const std::string& got) {
  throw FieldError(who + ": " + option + " must be " + allowed + ", got " + got, option, allowed);
}

void RequireFinitePositive(const std::string& who, const std::string& option, double value) {
  if (!std::isfinite(value) || !(value > 0)) {
    ThrowOption(who, option, "finite and > 0", FormatDouble(value));
  }
}

}  // namespace ipmc
