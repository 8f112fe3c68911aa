// Binding a mesh to markers and deforming it per frame (see marker_driven_mesh.h).
#include "registration/marker_driven_mesh.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "io/marker_trajectories.h"
#include "registration/obj_mesh.h"

namespace mocap {

void MarkerDrivenMeshOptions::Check() const {
  rbf.Check();
  icp.Check();
  if (!(max_alignment_rms_mm > 0.0))
    throw std::invalid_argument("max_alignment_rms_mm: " + std::to_string(max_alignment_rms_mm) + " must be > 0");
}

MarkerDrivenMesh::MarkerDrivenMesh(const std::vector<Eigen::Vector3d>& mesh_vertices,
                                   const std::vector<std::vector<int>>& mesh_faces,
                                   const std::vector<Eigen::Vector3d>& static_markers,
                                   const MarkerDrivenMeshOptions& options)
    : options_(options) {
  options.Check();
  for (size_t i = 0; i < static_markers.size(); ++i) {
    if (MarkerTrajectories::IsGap(static_markers[i])) continue;
    driving_.push_back(i);
    static_markers_.push_back(static_markers[i]);
  }
  if (driving_.size() < 4)
    throw std::invalid_argument("binding: " + std::to_string(driving_.size()) +
                                " markers in the static frame; at least 4 are needed");
  const std::vector<Eigen::Vector3d> normals = VertexNormals(mesh_vertices, mesh_faces);
  const RigidIcpResult fit =
      AlignRigidIcp(static_markers_, mesh_vertices, options.icp, mesh_faces.empty() ? nullptr : &normals);
  alignment_rms_mm_ = fit.rms_mm;
  if (!(fit.rms_mm <= options.max_alignment_rms_mm))
    throw std::invalid_argument("binding: the static markers lie " + std::to_string(fit.rms_mm) +
                                " mm RMS from the mesh after ICP, more than max_alignment_rms_mm " +
                                std::to_string(options.max_alignment_rms_mm));
  // ICP gave mesh_from_capture; its inverse places the mesh.
  capture_from_mesh_.rotation = fit.target_from_source.rotation.transpose();
  capture_from_mesh_.translation = -(capture_from_mesh_.rotation * fit.target_from_source.translation);
  bound_vertices_.reserve(mesh_vertices.size());
  for (const Eigen::Vector3d& v : mesh_vertices) bound_vertices_.push_back(capture_from_mesh_.Apply(v));
  weights_present_.assign(driving_.size(), true);
  weights_ = RbfInterpolator(static_markers_, options.rbf).Weights(bound_vertices_);
  bound_weights_ = weights_;
}

bool MarkerDrivenMesh::Deform(const std::vector<Eigen::Vector3d>& markers, std::vector<Eigen::Vector3d>* vertices) {
  if (markers.size() <= driving_.back())
    throw std::invalid_argument("Deform: " + std::to_string(markers.size()) + " markers, the binding has " +
                                std::to_string(driving_.back() + 1));
  std::vector<bool> present(driving_.size());
  std::vector<Eigen::Vector3d> centres;
  for (size_t i = 0; i < driving_.size(); ++i) {
    present[i] = !MarkerTrajectories::IsGap(markers[driving_[i]]);
    if (present[i]) centres.push_back(static_markers_[i]);
  }
  if (centres.size() < 4) return false;
  if (present != weights_present_) {
    weights_ = RbfInterpolator(centres, options_.rbf).Weights(bound_vertices_);
    weights_present_ = present;
  }
  Eigen::MatrixXd displacement(static_cast<Eigen::Index>(centres.size()), 3);
  Eigen::Index row = 0;
  for (size_t i = 0; i < driving_.size(); ++i)
    if (present[i]) displacement.row(row++) = (markers[driving_[i]] - static_markers_[i]).transpose();
  const Eigen::MatrixXd moved = weights_ * displacement;
  vertices->resize(bound_vertices_.size());
  for (size_t v = 0; v < bound_vertices_.size(); ++v)
    (*vertices)[v] = bound_vertices_[v] + moved.row(static_cast<Eigen::Index>(v)).transpose();
  return true;
}

}  // namespace mocap
