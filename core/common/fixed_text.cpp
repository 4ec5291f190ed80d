#include "core/common/fixed_text.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "core/common/error.h"

namespace bliskrun {

std::string fixed_text(double value, int decimals) {
  if (decimals < 0 || decimals > 17) throw ParameterError("decimals", "expected 0..17");
  // 309 digits before the point at most, a sign, the point and 17 decimals.
  char buffer[340];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::fixed, decimals);
  std::string text;
  if (ec == std::errc()) {
    text.assign(buffer, end);
  } else {  // cannot happen for a double within the buffer; printf then
    const int n = std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
    text.assign(buffer, n > 0 ? static_cast<size_t>(n) : 0);
  }
  // "-0.000" -> "0.000": a negative value that rounds to zero.
  if (text.size() > 1 && text[0] == '-' && text.find_first_not_of("0.", 1) == std::string::npos) text.erase(0, 1);
  return text;
}

std::string short_text(double value) {
  std::ostringstream os;
  os << value;
  return os.str();
}

std::string significant_text(double value, int digits) {
  if (digits < 1 || digits > 17) throw ParameterError("digits", "expected 1..17");
  if (!std::isfinite(value)) return short_text(value);
  if (value == 0) return "0";
  // The decimals that leave `digits` significant ones; a value that rounds
  // up to the next power of ten (9.996 -> 10.0) has one decimal fewer.
  int exponent = static_cast<int>(std::floor(std::log10(std::abs(value))));
  const double scaled = std::abs(value) / std::pow(10.0, exponent - digits + 1);
  if (std::round(scaled) >= std::pow(10.0, digits)) ++exponent;
  const int decimals = std::clamp(digits - 1 - exponent, 0, 17);
  if (decimals > 0) return fixed_text(value, decimals);
  // Large: round to `digits` significant digits, then print the integer.
  const double unit = std::pow(10.0, exponent - digits + 1);
  return fixed_text(std::round(value / unit) * unit, 0);
}

}  // namespace bliskrun
