#pragma once
// A number as fixed-point text: what printf("%.*f") writes, exactly (the
// correctly rounded decimal of the double, ties to even), through
// std::to_chars — several times cheaper than printf, which was a third of a
// Lua post's time a block (five or six numbers each).
#include <string>

namespace bliskrun {

// printf("%.*f", decimals, value) for decimals in [0, 17], except that a
// value which rounds to zero has no sign ("0.000", never "-0.000"): NC words
// must not read "-0".
std::string fixed_text(double value, int decimals);

// A number for a message: what a default std::ostream writes (6 significant
// digits, exponent when large or small), e.g. "0.5", "1e-07".
std::string short_text(double value);

// A number to `digits` significant digits (1..17) in fixed point, never
// with an exponent: what a reader takes in at a glance on a colour bar or
// in a table, e.g. 14.04 -> "14.0", 0.0123456 -> "0.0123", 98765 -> "98800",
// 0 -> "0". No sign on a value that rounds to zero.
std::string significant_text(double value, int digits = 3);

}  // namespace bliskrun
