// Wavefront OBJ meshes, as far as registration and mesh driving need them: vertex positions
// (`v x y z`, an optional w or colour ignored) and polygon faces (`f a b c ...`, each corner
// `v`, `v/vt`, `v//vn` or `v/vt/vn`, negative indices relative to the vertices read so far).
// Texture coordinates, normals, groups, materials and smoothing lines are skipped.
// Errors: std::runtime_error "<source>: line N: <reason>" (the io layer's rule).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace mocap {

struct ObjMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::vector<int>> faces;  // 0-based vertex indices, 3 or more per face
};

// Bounds of the reader (memory stays bounded on any input).
constexpr size_t kMaxObjFileBytes = size_t{512} << 20;
constexpr size_t kMaxObjFaceCorners = 64;

ObjMesh ParseObj(const std::string& text, const std::string& source);
ObjMesh ReadObj(const std::string& path);
// Unit normal of every vertex: the area-weighted sum of its faces' normals (a polygon's from
// Newell's method); (0, 0, 0) for a vertex in no face or only in degenerate ones.
std::vector<Eigen::Vector3d> VertexNormals(const std::vector<Eigen::Vector3d>& vertices,
                                           const std::vector<std::vector<int>>& faces);

// Vertices and faces; `vertices` replaces the mesh's own (same count) when given.
void WriteObj(const ObjMesh& mesh, const std::string& path, const std::vector<Eigen::Vector3d>* vertices = nullptr);

}  // namespace mocap
