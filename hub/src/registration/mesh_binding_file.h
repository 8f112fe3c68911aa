// A bound mesh as the console plays it (.mdb): what MarkerDrivenMesh computed once, so that the
// browser deforms the mesh per frame with one product (hub/web/js/mesh_binding.js reads it).
// Layout, little-endian:
//   magic     8 bytes "MOCAPMDB"
//   version   u32 = 1
//   vertices  u32 V (1..2^22)   triangles u32 T (0..2^23)   markers u32 n (4..4096)
//   names     per driving marker: u8 length (1..255), bytes (the capture's marker name)
//   static    f32 [n][3]  the driving markers' positions in the static frame, mm
//   bound     f32 [V][3]  the vertices as bound, in the capture's frame, mm
//   triangles u32 [T][3]  vertex indices (the OBJ's polygons as fans)
//   weights   f32 [V][n]  vertex v = bound[v] + sum_i weights[v][i] (marker_i - static_i)
// Errors: std::invalid_argument for bindings past the limits, std::runtime_error "<file>: ..."
// when the file cannot be written.
#pragma once

#include <string>
#include <vector>

#include "registration/marker_driven_mesh.h"

namespace mocap {

constexpr uint32_t kMeshBindingVersion = 1;

// `names`: the capture's marker names (indexed as the static frame given to the binding);
// `faces`: the mesh's polygons.
std::string EncodeMeshBinding(const MarkerDrivenMesh& driven, const std::vector<std::string>& names,
                              const std::vector<std::vector<int>>& faces);
void WriteMeshBindingFile(const std::string& bytes, const std::string& path);

}  // namespace mocap
