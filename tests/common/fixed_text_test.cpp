// fixed_text is printf's "%.*f" to the byte (the posts' number words rely on
// it: programs must not change when the formatting does), except that a
// value rounding to zero carries no sign.
#include "core/common/fixed_text.h"

#include "core/common/error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>

namespace bliskrun {
namespace {

std::string printf_fixed(double value, int decimals) {
  char buffer[400];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
  std::string text = buffer;
  if (text.size() > 1 && text[0] == '-' && text.find_first_not_of("0.", 1) == std::string::npos) text.erase(0, 1);
  return text;
}

TEST(FixedText, EqualsPrintfOnRandomValuesOfEveryMagnitude) {
  std::mt19937_64 rng(18);
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-12, 12), decimals(0, 9);
  for (int i = 0; i < 200000; ++i) {
    const double v = mantissa(rng) * std::pow(10.0, exponent(rng));
    const int d = decimals(rng);
    ASSERT_EQ(fixed_text(v, d), printf_fixed(v, d)) << v << " " << d;
  }
}

// Values on a decimal grid (what machine positions at the resolution are)
// and their halves: exact binary ties round to even, as printf does.
TEST(FixedText, EqualsPrintfOnTiesAndGridValues) {
  for (int d = 0; d <= 6; ++d) {
    for (long k = -20000; k <= 20000; ++k) {
      const double grid = static_cast<double>(k) * std::pow(10.0, -d);
      const double half = (static_cast<double>(k) + 0.5) * std::pow(10.0, -d);
      ASSERT_EQ(fixed_text(grid, d), printf_fixed(grid, d)) << grid << " " << d;
      ASSERT_EQ(fixed_text(half, d), printf_fixed(half, d)) << half << " " << d;
    }
  }
  EXPECT_EQ(fixed_text(0.125, 2), "0.12");
  EXPECT_EQ(fixed_text(0.375, 2), "0.38");
  EXPECT_EQ(fixed_text(2.5, 0), "2");
  EXPECT_EQ(fixed_text(-3.5, 0), "-4");
}

TEST(FixedText, ZeroHasNoSignAndSpecialsAreAsPrintf) {
  EXPECT_EQ(fixed_text(-0.0, 3), "0.000");
  EXPECT_EQ(fixed_text(-0.0004, 3), "0.000");
  EXPECT_EQ(fixed_text(-0.0005001, 3), "-0.001");
  EXPECT_EQ(fixed_text(-0.4, 0), "0");
  EXPECT_EQ(fixed_text(1e300, 3), printf_fixed(1e300, 3));
  EXPECT_EQ(fixed_text(std::numeric_limits<double>::infinity(), 3), printf_fixed(std::numeric_limits<double>::infinity(), 3));
  EXPECT_EQ(fixed_text(-std::numeric_limits<double>::infinity(), 3), "-inf");
  EXPECT_EQ(fixed_text(std::numeric_limits<double>::quiet_NaN(), 3), printf_fixed(std::numeric_limits<double>::quiet_NaN(), 3));
  EXPECT_THROW(fixed_text(1.0, 18), Error);
}

// Colour bars and tables: three significant digits, never an exponent
// (a new user read "9.928E-02" beside a caption in µm).
TEST(SignificantText, ThreeDigitsFixedPointNoExponent) {
  EXPECT_EQ(significant_text(14.04), "14.0");
  EXPECT_EQ(significant_text(-14.04), "-14.0");
  EXPECT_EQ(significant_text(0.09928), "0.0993");
  EXPECT_EQ(significant_text(99.28), "99.3");
  EXPECT_EQ(significant_text(9.996), "10.0");   // rounds up to the next power of ten
  EXPECT_EQ(significant_text(999.6), "1000");
  EXPECT_EQ(significant_text(98765.0), "98800");
  EXPECT_EQ(significant_text(1e-7), "0.000000100");
  EXPECT_EQ(significant_text(0.0), "0");
  EXPECT_EQ(significant_text(-0.0), "0");
  EXPECT_EQ(significant_text(30.0), "30.0");
  EXPECT_EQ(significant_text(2.5, 1), "3");
  for (double v : {1.234e-9, 5.5e-3, 0.5, 7.0, 123.456, 4.5e6})
    EXPECT_EQ(significant_text(v).find_first_of("eE"), std::string::npos) << v;
  EXPECT_THROW(significant_text(1.0, 0), Error);
}

}  // namespace
}  // namespace bliskrun
