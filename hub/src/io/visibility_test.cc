// Tests of visibility.tsv: round trip and clear errors.
#include "io/visibility.h"

#include <fstream>
#include <stdexcept>

#include <gtest/gtest.h>

#include "util/bounded_line.h"

namespace mocap {
namespace {

TEST(VisibilityTest, RoundTrip) {
  const std::string path = testing::TempDir() + "/visibility.tsv";
  VisibilityWriter writer;
  writer.Open(path, {"A", "B:C7"});
  writer.WriteFrame(10, {0, 3});
  writer.WriteFrame(12, {8, 1});
  writer.Close();
  const MarkerVisibility read = ReadVisibility(path);
  EXPECT_EQ(read.names, (std::vector<std::string>{"A", "B:C7"}));
  EXPECT_EQ(read.frame_numbers, (std::vector<uint64_t>{10, 12}));
  EXPECT_EQ(read.At(0, 0), 0);
  EXPECT_EQ(read.At(0, 1), 3);
  EXPECT_EQ(read.At(1, 0), 8);
  EXPECT_EQ(read.At(1, 1), 1);
}

TEST(VisibilityTest, Errors) {
  const auto expect_error = [](const std::string& text, const std::string& reason) {
    const std::string path = testing::TempDir() + "/bad_visibility.tsv";
    std::ofstream(path) << text;
    try {
      ReadVisibility(path);
      ADD_FAILURE() << text;
    } catch (const std::runtime_error& error) {
      EXPECT_NE(std::string(error.what()).find(reason), std::string::npos) << error.what();
    }
  };
  expect_error("", "empty visibility file");
  expect_error("time\tA\n", "header must start");
  expect_error("frame\tA\n1\t2\t3\n", "line 2: expected 2 cells");
  expect_error("frame\tA\n1\t-2\n", "bad camera count");
  expect_error("frame\tA\n2\t1\n2\t1\n", "must increase");
  EXPECT_THROW(ReadVisibility("/nonexistent/v.tsv"), std::runtime_error);
  // Names the writer cannot put back as read: the fuzzer's header "frame\t\0\0`..." was read
  // as one marker, written back as none, and the written file refused.
  expect_error(std::string("frame\tA\t\0x\n0\t1\t2\n", 17), "line 1: marker 2's name is empty");
  expect_error("frame\t\tB\n0\t1\t2\n", "marker 1's name is empty");
  expect_error("frame\tA\x01\n0\t1\n", "control character");
  // A line without end (/dev/zero, a damaged file) stops at 1 MiB instead of growing.
  expect_error(std::string(kMaxTextLineBytes + 10, '\0'), "line 1: longer than 1 MiB");
}

// Whatever the reader accepts, the writer puts back unchanged.
TEST(VisibilityTest, WhatIsReadIsWrittenBackUnchanged) {
  const std::string path = testing::TempDir() + "/visibility_in.tsv";
  const std::string again = testing::TempDir() + "/visibility_again.tsv";
  std::ofstream(path) << "frame\tA\tB C\t\xc3\xa9\n0\t1\t2\t3\n7\t0\t0\t65535\n";
  const MarkerVisibility read = ReadVisibility(path);
  VisibilityWriter writer;
  writer.Open(again, read.names);
  writer.WriteFrame(0, {1, 2, 3});
  writer.WriteFrame(7, {0, 0, 65535});
  writer.Close();
  const MarkerVisibility back = ReadVisibility(again);
  EXPECT_EQ(back.names, read.names);
  EXPECT_EQ(back.frame_numbers, read.frame_numbers);
  EXPECT_EQ(back.counts, read.counts);
}

}  // namespace
}  // namespace mocap
