// The plain-name rule: what may pass, and every way out of a directory refused.
#include "util/plain_name.h"

#include <gtest/gtest.h>

namespace mocap {
namespace {

TEST(PlainName, LettersDigitsDotDashUnderscore) {
  EXPECT_TRUE(PlainName("take_01.walk-2", 64));
  EXPECT_TRUE(PlainName("a", 1));
  EXPECT_TRUE(PlainName("x..y", 64));
}

TEST(PlainName, RefusesWaysOutAndHiddenNames) {
  for (const char* bad : {"", ".", "..", ".hidden", "../x", "a/b", "a\\b", "a b", "\xc3\xa4", "a\nb", "a%2fb"})
    EXPECT_FALSE(PlainName(bad, 64)) << bad;
}

TEST(PlainName, LengthLimitIsTheCallers) {
  EXPECT_TRUE(PlainName(std::string(64, 'a'), 64));
  EXPECT_FALSE(PlainName(std::string(65, 'a'), 64));
  EXPECT_TRUE(PlainName(std::string(128, 'a'), 128));
}

}  // namespace
}  // namespace mocap
