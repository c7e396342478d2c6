#include "sim/base/numbers.h"

#include <charconv>
#include <cstdarg>
#include <cstdio>
#include <system_error>

namespace ipmc {
namespace {

// std::from_chars takes a '-' but not a '+': drop one '+' before a digit,
// a point or a letter (not before another sign).
std::string_view WithoutPlus(std::string_view text) {
  if (text.size() > 1 && text[0] == '+' && text[1] != '+' && text[1] != '-') {
    text.remove_prefix(1);
  }
  return text;
}

// The whole of `text` as a T (after WithoutPlus), or nullopt.
template <typename T>
std::optional<T> ParseWhole(std::string_view text) {
  text = WithoutPlus(text);
  T value{};
  const char* end = text.data() + text.size();
  const std::from_chars_result result = std::from_chars(text.data(), end, value);
  if (text.empty() || result.ec != std::errc() || result.ptr != end) return std::nullopt;
  return value;
}

}  // namespace

std::optional<double> ParseDouble(std::string_view text) { return ParseWhole<double>(text); }

std::optional<long> ParseInteger(std::string_view text) { return ParseWhole<long>(text); }

std::string FormatDouble(double value, int significant_digits) {
  char buffer[64];
  // std::to_chars with a precision is defined as printf's "%.*g" in the C
  // locale; it skips printf's format parsing and is several times faster,
  // which counts in the CSVs of long records (a 200 s bench: 2.6 million
  // numbers). printf is the fallback for text longer than the buffer.
  const std::to_chars_result result = std::to_chars(
      buffer, buffer + sizeof(buffer), value, std::chars_format::general, significant_digits);
  if (result.ec == std::errc()) return std::string(buffer, result.ptr);
  std::snprintf(buffer, sizeof(buffer), "%.*g", significant_digits, value);
  return buffer;
}

std::string FormatShortest(double value) {
  char buffer[64];
  const std::to_chars_result result =
      std::to_chars(buffer, buffer + sizeof(buffer), value, std::chars_format::general);
  return std::string(buffer, result.ptr);
}

std::string FormatText(const char* format, ...) {
  va_list args;
  va_start(args, format);
  va_list copy;
  va_copy(copy, args);
  const int length = std::vsnprintf(nullptr, 0, format, copy);
  va_end(copy);
  std::string text(length > 0 ? length : 0, '\0');
  if (length > 0) std::vsnprintf(text.data(), text.size() + 1, format, args);
  va_end(args);
  return text;
}

}  // namespace ipmc
