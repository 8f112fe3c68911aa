// The .mdb binding: its header, names, triangles (polygons as fans) and weights are where the
// layout puts them, and applying its float32 weights to a frame's displacements gives the
// vertices MarkerDrivenMesh::Deform gives; refusals for bindings past the limits.
#include "registration/mesh_binding_file.h"

#include <cmath>
#include <cstring>
#include <stdexcept>

#include <gtest/gtest.h>

namespace mocap {
namespace {

template <typename T>
T At(const std::string& bytes, size_t offset) {
  T value;
  std::memcpy(&value, bytes.data() + offset, sizeof(T));
  return value;
}

TEST(MeshBindingFile, LayoutAndWeightsReproduceDeform) {
  // A 6 x 6 grid with two quads made of one polygon each and the rest triangles; five markers.
  std::vector<Eigen::Vector3d> grid;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) grid.emplace_back(20.0 * i, 20.0 * j, 2.0 * ((i * j) % 3));
  std::vector<std::vector<int>> faces = {{0, 1, 7, 6}, {1, 2, 8}, {2, 3, 9, 8}};
  const std::vector<Eigen::Vector3d> markers = {grid[0], grid[5], grid[30], grid[35], grid[14],
                                                Eigen::Vector3d::Constant(std::nan(""))};
  MarkerDrivenMeshOptions options;
  MarkerDrivenMesh driven(grid, faces, markers, options);
  const std::vector<std::string> names = {"A", "B", "C", "D", "E", "F"};
  const std::string bytes = EncodeMeshBinding(driven, names, faces);

  ASSERT_EQ(bytes.substr(0, 8), "MOCAPMDB");
  EXPECT_EQ(At<uint32_t>(bytes, 8), kMeshBindingVersion);
  EXPECT_EQ(At<uint32_t>(bytes, 12), 36u);
  EXPECT_EQ(At<uint32_t>(bytes, 16), 5u);  // 2 + 1 + 2 triangles
  EXPECT_EQ(At<uint32_t>(bytes, 20), 5u);  // F is missing in the static frame: not driving
  size_t pos = 24;
  for (const char* name : {"A", "B", "C", "D", "E"}) {
    ASSERT_EQ(At<uint8_t>(bytes, pos), 1);
    EXPECT_EQ(bytes[pos + 1], name[0]);
    pos += 2;
  }
  pos += 5 * 12;  // static positions
  const size_t bound = pos;
  pos += 36 * 12;
  const std::vector<uint32_t> fans = {0, 1, 7, 0, 7, 6, 1, 2, 8, 2, 3, 9, 2, 9, 8};
  for (size_t i = 0; i < fans.size(); ++i) EXPECT_EQ(At<uint32_t>(bytes, pos + 4 * i), fans[i]) << i;
  pos += 4 * fans.size();
  ASSERT_EQ(bytes.size(), pos + 36 * 5 * 4);

  std::vector<Eigen::Vector3d> frame = markers;
  for (size_t i = 0; i < 5; ++i) frame[i] += Eigen::Vector3d(3.0 * i, -2.0, 1.5 * i * i);
  std::vector<Eigen::Vector3d> expected;
  ASSERT_TRUE(driven.Deform(frame, &expected));
  for (size_t v = 0; v < 36; ++v) {
    Eigen::Vector3d p(At<float>(bytes, bound + 12 * v), At<float>(bytes, bound + 12 * v + 4),
                      At<float>(bytes, bound + 12 * v + 8));
    for (size_t i = 0; i < 5; ++i) p += At<float>(bytes, pos + 4 * (v * 5 + i)) * (frame[i] - markers[i]);
    EXPECT_LT((p - expected[v]).norm(), 1e-4) << v;
  }
}

TEST(MeshBindingFile, RefusesUnnamedMarkersAndFacesOutsideTheMesh) {
  std::vector<Eigen::Vector3d> grid;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) grid.emplace_back(30.0 * i, 30.0 * j, 3.0 * ((i + j) % 2));
  const std::vector<Eigen::Vector3d> markers = {grid[0], grid[3], grid[12], grid[15]};
  MarkerDrivenMesh driven(grid, {}, markers, MarkerDrivenMeshOptions());
  EXPECT_THROW(EncodeMeshBinding(driven, {"A", "B", "C"}, {}), std::invalid_argument);
  EXPECT_THROW(EncodeMeshBinding(driven, {"A", "B", "", "D"}, {}), std::invalid_argument);
  EXPECT_THROW(EncodeMeshBinding(driven, {"A", "B", "C", "D"}, {{0, 1, 16}}), std::invalid_argument);
  EXPECT_NO_THROW(EncodeMeshBinding(driven, {"A", "B", "C", "D"}, {{0, 1, 5}}));
}

}  // namespace
}  // namespace mocap
