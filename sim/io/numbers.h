// Number formatting for error messages.
#pragma once

#include <limits>
#include <sstream>
#include <string>

namespace ipmc {

// A double with enough digits to round-trip, for error messages.
inline std::string FormatDouble(double value) {
  std::ostringstream out;
  out.precision(std::numeric_limits<double>::max_digits10);
  out << value;
  return out.str();
}

}  // namespace ipmc
