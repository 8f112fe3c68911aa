// Markers that drive a mesh (seed 003, chapter 5): a mesh is bound once to the markers of a
// static frame, then every captured frame moves its vertices.
//   Bind:   rigid ICP of the static markers onto the mesh's vertices (k-d tree + Kabsch, then
//           point-to-plane on the faces' normals) places the mesh in the capture's frame; the markers' static positions become RBF centres
//           and each vertex's weights on them are computed once.
//   Deform: a frame's vertices are their bound positions plus the RBF interpolation of the
//           markers' displacements from the static frame: one (vertices x markers) matrix
//           product. A marker missing in the frame is left out: the weights are recomputed for
//           the markers present (kept while the same markers are missing) and at least 4 must be.
// Errors: std::invalid_argument (options, too few static markers, a failed alignment).
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "geometry/rigid_fit.h"
#include "registration/rbf.h"
#include "registration/rigid_icp.h"

namespace mocap {

struct MarkerDrivenMeshOptions {
  RbfOptions rbf;
  RigidIcpOptions icp;
  // Refuse a binding whose ICP leaves the markers farther than this (RMS, mm) from the mesh's
  // vertices: the mesh and the markers do not belong together, or the start was too far off.
  double max_alignment_rms_mm = 20.0;

  void Check() const;
};

class MarkerDrivenMesh {
 public:
  // `mesh_vertices` in the mesh's own frame, `mesh_faces` their polygons (none: point-to-point ICP
  // only); `static_markers` one per marker of the capture, a gap (NaN) for those missing in the
  // static frame (they never drive the mesh).
  MarkerDrivenMesh(const std::vector<Eigen::Vector3d>& mesh_vertices, const std::vector<std::vector<int>>& mesh_faces,
                   const std::vector<Eigen::Vector3d>& static_markers, const MarkerDrivenMeshOptions& options);

  const SimilarityTransform& capture_from_mesh() const { return capture_from_mesh_; }
  double alignment_rms_mm() const { return alignment_rms_mm_; }
  const std::vector<Eigen::Vector3d>& bound_vertices() const { return bound_vertices_; }
  size_t NumDrivingMarkers() const { return driving_.size(); }
  // The driving markers' indices and static positions, and each vertex's RBF weights on them
  // (vertices x driving markers) as bound, before any Deform left a marker out.
  const std::vector<size_t>& driving_markers() const { return driving_; }
  const std::vector<Eigen::Vector3d>& static_markers() const { return static_markers_; }
  const Eigen::MatrixXd& bound_weights() const { return bound_weights_; }

  // The vertices for one frame's markers (same count as the static ones, gaps allowed). Returns
  // false, leaving *vertices untouched, when fewer than 4 driving markers are present.
  bool Deform(const std::vector<Eigen::Vector3d>& markers, std::vector<Eigen::Vector3d>* vertices);

 private:
  MarkerDrivenMeshOptions options_;
  SimilarityTransform capture_from_mesh_;
  double alignment_rms_mm_ = 0.0;
  std::vector<Eigen::Vector3d> bound_vertices_;
  std::vector<size_t> driving_;                 // marker indices present in the static frame
  std::vector<Eigen::Vector3d> static_markers_; // their static positions
  std::vector<bool> weights_present_;           // which driving markers `weights_` is for
  Eigen::MatrixXd weights_;                     // vertices x present driving markers
  Eigen::MatrixXd bound_weights_;               // vertices x driving markers
};

}  // namespace mocap
