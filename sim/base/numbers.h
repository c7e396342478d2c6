// Numbers as text, read and written by one set of rules, and pi.
//
// Reading is strict: the whole text must be one number, with no blanks
// around it: an optional sign, digits with an optional point and
// exponent ("1", "-2.5", "+3e-4"), or inf / nan as std::from_chars
// reads them (callers that need a finite value check). Locale-independent.
//
// Writing: FormatDouble(v, d) is printf's "%.*g" with d significant
// digits (the default 17, max_digits10, reads back exactly; the same as a
// stream at that precision); FormatShortest(v) is the shortest text that
// reads back exactly ("0.001", "1000", "1e+20"). FormatText is printf into
// a string, for reports and tables.
#pragma once

#include <limits>
#include <optional>
#include <string>
#include <string_view>

namespace ipmc {

constexpr double kPi = 3.14159265358979323846;
constexpr double kTwoPi = 2.0 * kPi;

constexpr int kRoundTripDigits = std::numeric_limits<double>::max_digits10;

// The whole of `text` as a double, or nullopt. Out-of-range magnitudes
// (1e400) are not numbers.
std::optional<double> ParseDouble(std::string_view text);

// The whole of `text` as a whole number (optional sign, decimal digits),
// or nullopt (also when it does not fit a long).
std::optional<long> ParseInteger(std::string_view text);

std::string FormatDouble(double value, int significant_digits = kRoundTripDigits);
std::string FormatShortest(double value);
std::string FormatText(const char* format, ...) __attribute__((format(printf, 1, 2)));

}  // namespace ipmc
