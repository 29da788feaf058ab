// The tools' flag reader: strict numbers, clear messages naming the flag.
#include <gtest/gtest.h>

#include <limits>

#include "occlusion_env/tools/arguments.hpp"

namespace occlusion_env::tools {
namespace {

/// The message of the ArgumentError `call` throws ("" when it throws none).
template <typename Call>
std::string errorOf(Call call) {
  try {
    call();
  } catch (const ArgumentError& error) {
    return error.what();
  }
  return "";
}

TEST(ArgumentsTest, IntegersAreStrict) {
  EXPECT_EQ(parseInteger("--n", "42", 0, 100), 42);
  EXPECT_EQ(parseInteger("--n", "-7", -10, 10), -7);
  EXPECT_EQ(parseInteger("--n", "+7", -10, 10), 7);
  for (const char* bad : {"", "1.5", "12px", " 3", "3 ", "0x10", "-", "1e3"}) {
    EXPECT_NE(errorOf([&] { parseInteger("--n", bad, 0, 100000); }), "") << bad;
  }
  EXPECT_EQ(errorOf([] { parseInteger("--size", "101", 0, 100); }),
            "--size expects an integer in [0, 100], got '101'");
  EXPECT_NE(errorOf([] { parseInteger("--n", "99999999999999999999999", 0, 10); }), "");
}

TEST(ArgumentsTest, UnsignedKeepsAllSixtyFourBits) {
  EXPECT_EQ(parseUnsigned("--seed", "18446744073709551615"),
            std::numeric_limits<std::uint64_t>::max());
  EXPECT_EQ(parseUnsigned("--seed", "9007199254740993"), 9007199254740993ull);  // > 2^53
  for (const char* bad : {"-1", "+1", "18446744073709551616", "1.0", ""}) {
    EXPECT_NE(errorOf([&] { parseUnsigned("--seed", bad); }), "") << bad;
  }
}

TEST(ArgumentsTest, NumbersAreFiniteAndInRange) {
  EXPECT_DOUBLE_EQ(parseNumber("--x", "0.25", 0.0, 1.0), 0.25);
  EXPECT_DOUBLE_EQ(parseNumber("--x", "-1e-3", -1.0, 1.0), -1e-3);
  for (const char* bad : {"nan", "inf", "1.5", "0.5x", "", " 0.5"}) {
    EXPECT_NE(errorOf([&] { parseNumber("--x", bad, 0.0, 1.0); }), "") << bad;
  }
}

TEST(ArgumentsTest, ListsRefuseEmptyItems) {
  EXPECT_EQ(splitList("--agents", "random,gradient"),
            (std::vector<std::string>{"random", "gradient"}));
  EXPECT_EQ(splitList("--agents", "one"), (std::vector<std::string>{"one"}));
  for (const char* bad : {"", ",", "a,", ",a", "a,,b"}) {
    EXPECT_NE(errorOf([&] { splitList("--agents", bad); }), "") << bad;
  }
}

}  // namespace
}  // namespace occlusion_env::tools
