// Bounded line reading: the lines std::getline gives, and a clear stop where it would grow forever.
#include "util/bounded_line.h"

#include <sstream>

#include <gtest/gtest.h>

namespace mocap {
namespace {

std::vector<std::string> Lines(const std::string& text) {
  std::istringstream in(text);
  std::vector<std::string> lines;
  std::string line;
  for (LineRead read; (read = ReadBoundedLine(in, &line, 8)) != LineRead::kEnd;) {
    EXPECT_EQ(read, LineRead::kLine);
    lines.push_back(line);
  }
  return lines;
}

TEST(BoundedLine, GivesTheLinesGetlineGives) {
  for (const std::string& text : {std::string(""), std::string("a"), std::string("a\n"), std::string("a\nbc"),
                                   std::string("\n\nx\n"), std::string("12345678\n"), std::string("a\r\nb")}) {
    std::istringstream in(text);
    std::vector<std::string> expected;
    for (std::string line; std::getline(in, line);) expected.push_back(line);
    EXPECT_EQ(Lines(text), expected) << "'" << text << "'";
  }
}

TEST(BoundedLine, StopsAtTheBoundWithoutReadingFurther) {
  std::istringstream in("123456789abc\nnext\n");
  std::string line;
  EXPECT_EQ(ReadBoundedLine(in, &line, 8), LineRead::kTooLong);
  EXPECT_EQ(line, "12345678");
  // A stream of NULs without end (what /dev/zero gives) stops at the bound too.
  std::string zeros(1 << 16, '\0');
  std::istringstream endless(zeros);
  EXPECT_EQ(ReadBoundedLine(endless, &line, 1000), LineRead::kTooLong);
  EXPECT_EQ(line.size(), 1000u);
}

}  // namespace
}  // namespace mocap
