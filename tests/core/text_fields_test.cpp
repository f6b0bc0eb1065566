// Strict numbers from text (core/text_fields.h): the whole field or nothing.
#include <gtest/gtest.h>

#include <cmath>

#include "core/text_fields.h"

namespace vf {
namespace {

TEST(TextFields, TheWholeFieldIsTheNumberOrNothing) {
  double d = 0;
  EXPECT_TRUE(parseDouble("1.5e-3", d));
  EXPECT_DOUBLE_EQ(d, 1.5e-3);
  EXPECT_TRUE(parseDouble("-inf", d));  // ScanNet's lost poses
  EXPECT_TRUE(std::isinf(d));
  EXPECT_FALSE(parseFiniteDouble("-inf", d));
  EXPECT_FALSE(parseFiniteDouble("nan", d));
  for (const char* bad : {"", " ", "12abc", "1.5 ", "0x", "--1", "1,5"}) EXPECT_FALSE(parseDouble(bad, d)) << bad;

  float f = 0;
  EXPECT_TRUE(parseFiniteFloat("0.25", f));
  EXPECT_FLOAT_EQ(f, 0.25f);
  EXPECT_FALSE(parseFiniteFloat("1e39", f));  // past float's range: would become inf

  int i = 0;
  EXPECT_TRUE(parseInt("-42", i));
  EXPECT_EQ(i, -42);
  EXPECT_TRUE(parseInt("2147483647", i));
  for (const char* bad : {"", "2147483648", "-2147483649", "99999999999999999999", "1.0", "7x", " 7"})
    EXPECT_FALSE(parseInt(bad, i)) << bad;
}

}  // namespace
}  // namespace vf
