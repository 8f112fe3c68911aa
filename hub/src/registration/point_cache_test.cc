// Point caches: the PC2 and MDD headers, byte orders and values as Blender reads them; wrong
// extensions, frame sizes and short files refused.
#include "registration/point_cache.h"

#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include <gtest/gtest.h>

#include "util/temporary_directory_testing.h"

namespace mocap {
namespace {

std::string Slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

uint32_t U32(const std::string& bytes, size_t offset, bool big_endian) {
  uint32_t value = 0;
  for (int i = 0; i < 4; ++i) {
    const uint32_t byte = static_cast<unsigned char>(bytes[offset + static_cast<size_t>(i)]);
    value |= byte << (big_endian ? 8 * (3 - i) : 8 * i);
  }
  return value;
}

float F32(const std::string& bytes, size_t offset, bool big_endian) {
  const uint32_t bits = U32(bytes, offset, big_endian);
  float value;
  std::memcpy(&value, &bits, 4);
  return value;
}

std::vector<Eigen::Vector3d> Frame(int f) {
  return {Eigen::Vector3d(f, 1.5, -2), Eigen::Vector3d(10 + f, 20, 30.25)};
}

TEST(PointCache, Pc2LayoutAndValues) {
  const testing::TemporaryDirectory dir("point_cache");
  const std::string path = dir.File("face.PC2");
  PointCacheWriter writer;
  writer.Open(path, 2, 3, 60.0);
  for (int f = 0; f < 3; ++f) writer.WriteFrame(Frame(f));
  writer.Close();
  const std::string bytes = Slurp(path);
  ASSERT_EQ(bytes.size(), 32u + 3 * 2 * 12);
  EXPECT_EQ(bytes.substr(0, 12), std::string("POINTCACHE2\0", 12));
  EXPECT_EQ(U32(bytes, 12, false), 1u);
  EXPECT_EQ(U32(bytes, 16, false), 2u);
  EXPECT_EQ(F32(bytes, 20, false), 0.0f);
  EXPECT_EQ(F32(bytes, 24, false), 1.0f);
  EXPECT_EQ(U32(bytes, 28, false), 3u);
  EXPECT_EQ(F32(bytes, 32 + 2 * 12 + 12 + 8, false), 30.25f);  // frame 1, vertex 1, z
  EXPECT_EQ(F32(bytes, 32 + 2 * 2 * 12, false), 2.0f);          // frame 2, vertex 0, x
}

TEST(PointCache, MddLayoutAndValues) {
  const testing::TemporaryDirectory dir("point_cache");
  const std::string path = dir.File("face.mdd");
  PointCacheWriter writer;
  writer.Open(path, 2, 3, 50.0);
  for (int f = 0; f < 3; ++f) writer.WriteFrame(Frame(f));
  writer.Close();
  const std::string bytes = Slurp(path);
  ASSERT_EQ(bytes.size(), 8u + 3 * 4 + 3 * 2 * 12);
  EXPECT_EQ(U32(bytes, 0, true), 3u);
  EXPECT_EQ(U32(bytes, 4, true), 2u);
  EXPECT_FLOAT_EQ(F32(bytes, 8 + 2 * 4, true), 0.04f);  // frame 2 at 50 Hz
  EXPECT_EQ(F32(bytes, 20 + 2 * 12 + 12, true), 11.0f); // frame 1, vertex 1, x
}

TEST(PointCache, Refusals) {
  const testing::TemporaryDirectory dir("point_cache");
  EXPECT_THROW(PointCacheFormatOf("a.obj"), std::invalid_argument);
  PointCacheWriter writer;
  writer.Open(dir.File("short.pc2"), 2, 3, 60.0);
  EXPECT_THROW(writer.WriteFrame({Eigen::Vector3d::Zero()}), std::invalid_argument);
  writer.WriteFrame(Frame(0));
  EXPECT_THROW(writer.Close(), std::runtime_error);  // 1 of 3 frames
  PointCacheWriter none;
  EXPECT_THROW(none.Open(dir.File("none.mdd"), 0, 3, 60.0), std::invalid_argument);
  EXPECT_THROW(none.Open(dir.File("missing/dir.mdd"), 2, 3, 60.0), std::runtime_error);
}

}  // namespace
}  // namespace mocap
