#include "occlusion_env/common/errors.hpp"

#include <gtest/gtest.h>

namespace occlusion_env {
namespace {

TEST(ErrorsTest, QuotedEscapesControlCharactersAndCutsLongText) {
  EXPECT_EQ(quoted("chair"), "'chair'");
  // A NUL would end what() early and lose the closing quote.
  const std::string with_nul("a\0b", 3);
  const InvalidArgumentError error("unknown id " + quoted(with_nul));
  EXPECT_STREQ(error.what(), "unknown id 'a\\0b'");
  EXPECT_EQ(quoted("x\ny\x01"), "'x\\ny\\x01'");
  const std::string cut = quoted(std::string(100, 'z'), 10);
  EXPECT_EQ(cut, "'zzzzzzzzzz...' (100 chars)");
}

}  // namespace
}  // namespace occlusion_env
