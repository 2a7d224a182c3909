// util::parseFiniteNumber: how every typed number is read (src/util/parse_number.h).
#include <gtest/gtest.h>

#include <limits>

#include "util/parse_number.h"

namespace bounce::util {
namespace {

TEST(ParseNumber, ReadsDecimalAndScientificNumbers) {
  EXPECT_EQ(parseFiniteNumber("0.25"), 0.25);
  EXPECT_EQ(parseFiniteNumber("-3"), -3.0);
  EXPECT_EQ(parseFiniteNumber("1e20"), 1e20);
  EXPECT_EQ(parseFiniteNumber("1.7976931348623157e308"), std::numeric_limits<double>::max());
}

TEST(ParseNumber, NumbersTooSmallForADoubleOrAFloatAreNumbers) {
  EXPECT_EQ(parseFiniteNumber("1e-46"), 1e-46);  // below a float's smallest subnormal: float(...) is 0
  EXPECT_EQ(float(*parseFiniteNumber("1e-46")), 0.0f);
  ASSERT_TRUE(parseFiniteNumber("4e-320").has_value());  // a double subnormal
  EXPECT_GT(*parseFiniteNumber("4e-320"), 0.0);
  EXPECT_EQ(parseFiniteNumber("1e-400"), 0.0);
  EXPECT_EQ(parseFiniteNumber("-1e-400"), -0.0);
}

TEST(ParseNumber, RefusesWhatIsNotAFiniteNumber) {
  for (const char* text : {"", "nan", "NaN", "inf", "-inf", "infinity", "1e309", "-1e309", "1.5x", " 1", "1 ", "0x10",
                           "one", "1,5", "--1"})
    EXPECT_FALSE(parseFiniteNumber(text).has_value()) << "'" << text << "'";
}

}  // namespace
}  // namespace bounce::util
