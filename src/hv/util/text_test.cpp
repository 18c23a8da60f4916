#include "hv/util/text.h"

#include <gtest/gtest.h>

namespace hv {
namespace {

TEST(Text, TrimFieldLowerAndShown) {
  EXPECT_EQ(trimField(" \t\"x,y\"\r"), "x,y");
  EXPECT_EQ(trimField("\""), "\"");
  EXPECT_EQ(trimField("  "), "");
  EXPECT_EQ(asciiLower("AbC-É"), std::string("abc-") + "É");
  EXPECT_EQ(shownText(std::string("a\x01") + "b"), "a?b");
  EXPECT_EQ(shownText(std::string(41, 'z')), std::string(40, 'z') + "...");
  EXPECT_EQ(shownText(std::string(40, 'z')), std::string(40, 'z'));
}

}  // namespace
}  // namespace hv
