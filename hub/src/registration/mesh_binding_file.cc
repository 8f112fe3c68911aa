// The .mdb writer (layout in mesh_binding_file.h).
#include "registration/mesh_binding_file.h"

#include <cstring>
#include <fstream>
#include <stdexcept>

namespace mocap {
namespace {

template <typename T>
void Put(std::string& out, T value) {
  char raw[sizeof(T)];
  std::memcpy(raw, &value, sizeof(T));  // the hub's targets are little-endian (x86-64, aarch64)
  out.append(raw, sizeof(T));
}

void PutPoint(std::string& out, const Eigen::Vector3d& p) {
  for (int a = 0; a < 3; ++a) Put<float>(out, static_cast<float>(p[a]));
}

}  // namespace

std::string EncodeMeshBinding(const MarkerDrivenMesh& driven, const std::vector<std::string>& names,
                              const std::vector<std::vector<int>>& faces) {
  const std::vector<Eigen::Vector3d>& vertices = driven.bound_vertices();
  const std::vector<size_t>& driving = driven.driving_markers();
  std::vector<uint32_t> triangles;
  for (const std::vector<int>& face : faces)
    for (size_t i = 2; i < face.size(); ++i)
      for (int v : {face[0], face[i - 1], face[i]}) {
        if (v < 0 || static_cast<size_t>(v) >= vertices.size())
          throw std::invalid_argument("mesh binding: face vertex " + std::to_string(v) + " is outside the mesh");
        triangles.push_back(static_cast<uint32_t>(v));
      }
  if (vertices.empty() || vertices.size() > (size_t{1} << 22))
    throw std::invalid_argument("mesh binding: " + std::to_string(vertices.size()) + " vertices is outside 1..2^22");
  if (triangles.size() / 3 > (size_t{1} << 23))
    throw std::invalid_argument("mesh binding: " + std::to_string(triangles.size() / 3) + " triangles is past 2^23");
  if (driving.size() < 4 || driving.size() > 4096)
    throw std::invalid_argument("mesh binding: " + std::to_string(driving.size()) + " driving markers is outside 4..4096");
  std::string out("MOCAPMDB");
  Put<uint32_t>(out, kMeshBindingVersion);
  Put<uint32_t>(out, static_cast<uint32_t>(vertices.size()));
  Put<uint32_t>(out, static_cast<uint32_t>(triangles.size() / 3));
  Put<uint32_t>(out, static_cast<uint32_t>(driving.size()));
  for (size_t marker : driving) {
    if (marker >= names.size() || names[marker].empty() || names[marker].size() > 255)
      throw std::invalid_argument("mesh binding: marker " + std::to_string(marker) + " has no name of 1..255 bytes");
    Put<uint8_t>(out, static_cast<uint8_t>(names[marker].size()));
    out += names[marker];
  }
  for (const Eigen::Vector3d& p : driven.static_markers()) PutPoint(out, p);
  for (const Eigen::Vector3d& p : vertices) PutPoint(out, p);
  for (uint32_t v : triangles) Put<uint32_t>(out, v);
  const Eigen::MatrixXd& weights = driven.bound_weights();
  for (Eigen::Index v = 0; v < weights.rows(); ++v)
    for (Eigen::Index i = 0; i < weights.cols(); ++i) Put<float>(out, static_cast<float>(weights(v, i)));
  return out;
}

void WriteMeshBindingFile(const std::string& bytes, const std::string& path) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw std::runtime_error(path + ": cannot open for writing");
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) throw std::runtime_error(path + ": write failed");
}

}  // namespace mocap
