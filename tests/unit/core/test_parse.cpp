#include <gtest/gtest.h>

#include "fvx/core/error.hpp"
#include "fvx/core/parse.hpp"

namespace fvx {
namespace {

TEST(Parse, AcceptsWholeNumbersOnly) {
  EXPECT_DOUBLE_EQ(parse_double("0.05", "--resolution"), 0.05);
  EXPECT_DOUBLE_EQ(parse_double("-1e-3", "x"), -1e-3);
  for (const char* bad : {"", "abc", "0.05m", "5cm", " 1", "1 ", "nan", "inf", "1e999", "0x"}) {
    EXPECT_THROW(parse_double(bad, "--resolution"), UsageError) << "'" << bad << "'";
  }
}

TEST(Parse, MessageNamesTheOptionAndTheRange) {
  try {
    parse_double_in("0", "--resolution", 0.001, 10.0);
    FAIL();
  } catch (const UsageError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("--resolution"), std::string::npos) << m;
    EXPECT_NE(m.find("0.001"), std::string::npos) << m;
  }
  EXPECT_THROW(parse_double_in("0", "x", 0.0, 1.0, true), UsageError);
  EXPECT_DOUBLE_EQ(parse_double_in("0", "x", 0.0, 1.0), 0.0);
  EXPECT_DOUBLE_EQ(parse_double_in("1", "x", 0.0, 1.0), 1.0);
}

TEST(Parse, Integers) {
  EXPECT_EQ(parse_int_in("42", "n", 1, 100), 42);
  EXPECT_THROW(parse_int_in("4.2", "n", 1, 100), UsageError);
  EXPECT_THROW(parse_int_in("0", "n", 1, 100), UsageError);
  EXPECT_THROW(parse_int_in("99999999999999999999", "n", 1, 100), UsageError);
}

TEST(Parse, Lists) {
  EXPECT_EQ(parse_double_list("1,2.5,-3", "--p", 3), (std::vector<double>{1, 2.5, -3}));
  EXPECT_THROW(parse_double_list("1,2", "--p", 3), UsageError);
  EXPECT_THROW(parse_double_list("1,,3", "--p", 3), UsageError);
  EXPECT_THROW(parse_double_list("1,2,3,", "--p", 3), UsageError);
}

}  // namespace
}  // namespace fvx
