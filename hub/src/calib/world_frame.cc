// L-frame search: reconstruct each frame with the recon layer, match the model by pairwise
// distances (pruned depth-first search over assignments), average the matched markers over the
// frames, then one Kabsch fit. Floor levelling: plane by SVD, minimal rotation onto up.
#include "calib/world_frame.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>
#include <stdexcept>
#include <string>

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include "recon/reconstructor.h"

namespace mocap {
namespace {

// Every marker must stay recognisable: no other ordering of the model fits the model itself.
void CheckModel(const std::vector<Eigen::Vector3d>& model, double tolerance_mm) {
  if (model.size() < 3) throw std::invalid_argument("an L-frame needs at least 3 markers");
  if (model.size() > 8) throw std::invalid_argument("an L-frame has at most 8 markers");
  FitRigid(model, model);  // throws for collinear markers
  std::vector<size_t> order(model.size());
  std::iota(order.begin(), order.end(), 0);
  while (std::next_permutation(order.begin(), order.end())) {
    std::vector<Eigen::Vector3d> permuted;
    for (size_t i : order) permuted.push_back(model[i]);
    if (AlignmentRms(FitRigid(permuted, model), permuted, model) < 2.0 * tolerance_mm) {
      throw std::invalid_argument("the L-frame's markers cannot be told apart (symmetric geometry): make all "
                                  "distances between markers differ");
    }
  }
}

}  // namespace

std::vector<Eigen::Vector3d> DefaultLFrame(int up_axis) {
  if (up_axis < 0 || up_axis > 2) throw std::invalid_argument("up axis must be 0, 1 or 2");
  const Eigen::Vector3d first = Eigen::Vector3d::Unit((up_axis + 1) % 3);
  const Eigen::Vector3d second = Eigen::Vector3d::Unit((up_axis + 2) % 3);
  return {Eigen::Vector3d::Zero(), 200.0 * first, 500.0 * first, 350.0 * second};
}

void LFrameOptions::Check() const {
  if (!(max_fit_rms_mm > 0.0)) throw std::invalid_argument("max_fit_rms_mm must be > 0");
  if (min_frames < 1) throw std::invalid_argument("min_frames must be >= 1");
}

bool MatchModel(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& model,
                double max_fit_rms_mm, std::vector<Eigen::Vector3d>* matched) {
  const size_t n = model.size();
  if (points.size() < n) return false;
  // Pairwise distances of a right assignment agree within a few times the fit tolerance.
  const double gate = 4.0 * max_fit_rms_mm;
  std::vector<size_t> chosen;
  std::vector<bool> used(points.size(), false);
  double best_rms = max_fit_rms_mm;
  bool found = false;
  std::function<void()> search = [&]() {
    const size_t k = chosen.size();
    if (k == n) {
      std::vector<Eigen::Vector3d> candidate;
      for (size_t index : chosen) candidate.push_back(points[index]);
      const double rms = AlignmentRms(FitRigid(candidate, model), candidate, model);
      if (rms <= best_rms) {
        best_rms = rms;
        *matched = candidate;
        found = true;
      }
      return;
    }
    for (size_t p = 0; p < points.size(); ++p) {
      if (used[p]) continue;
      bool consistent = true;
      for (size_t j = 0; j < k && consistent; ++j) {
        const double measured = (points[p] - points[chosen[j]]).norm();
        consistent = std::abs(measured - (model[k] - model[j]).norm()) <= gate;
      }
      if (!consistent) continue;
      used[p] = true;
      chosen.push_back(p);
      search();
      chosen.pop_back();
      used[p] = false;
    }
  };
  search();
  return found;
}

WorldFrameFit LocateLFrame(const std::vector<FrameSet>& frames, const Rig& rig,
                           const std::vector<Eigen::Vector3d>& model, const LFrameOptions& options) {
  options.Check();
  CheckModel(model, options.max_fit_rms_mm);
  ReconstructorOptions recon_options;
  recon_options.use_predictions = false;
  Reconstructor reconstructor(rig, recon_options);
  std::vector<ReconstructedPoint> reconstructed;
  std::vector<Eigen::Vector3d> sums(model.size(), Eigen::Vector3d::Zero());
  WorldFrameFit fit;
  for (const FrameSet& set : frames) {
    reconstructor.Process(set, {}, &reconstructed);
    if (reconstructed.size() < model.size()) continue;
    std::vector<Eigen::Vector3d> points, matched;
    for (const ReconstructedPoint& point : reconstructed) points.push_back(point.point_in_world);
    if (!MatchModel(points, model, options.max_fit_rms_mm, &matched)) continue;
    for (size_t k = 0; k < model.size(); ++k) sums[k] += matched[k];
    ++fit.frames_used;
  }
  if (fit.frames_used < options.min_frames) {
    throw std::runtime_error("the L-frame (" + std::to_string(model.size()) + " markers) was found in " +
                             std::to_string(fit.frames_used) + " frames (need " + std::to_string(options.min_frames) +
                             "): lay it where at least three cameras see every marker, keep other markers out of "
                             "view, and check its geometry");
  }
  for (const Eigen::Vector3d& sum : sums) fit.measured.push_back(sum / fit.frames_used);
  fit.new_from_old = FitRigid(fit.measured, model);
  fit.fit_rms_mm = AlignmentRms(fit.new_from_old, fit.measured, model);
  return fit;
}

WorldFrameFit LevelOnFloor(const std::vector<Eigen::Vector3d>& floor_points, const Rig& rig, int up_axis) {
  if (up_axis < 0 || up_axis > 2) throw std::invalid_argument("up axis must be 0, 1 or 2");
  if (floor_points.size() < 3) throw std::invalid_argument("levelling on the floor needs at least 3 points");
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : floor_points) centroid += p;
  centroid /= static_cast<double>(floor_points.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& p : floor_points) scatter += (p - centroid) * (p - centroid).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(scatter);
  // Eigenvalues ascending: the second must be clearly non-zero, else the points form a line.
  if (!(eigen.eigenvalues()(1) > 1e-6 * eigen.eigenvalues()(2)) || !(eigen.eigenvalues()(2) > 0.0)) {
    throw std::invalid_argument("floor points are collinear: the floor plane is undetermined");
  }
  Eigen::Vector3d normal = eigen.eigenvectors().col(0);
  Eigen::Vector3d towards_cameras = Eigen::Vector3d::Zero();
  for (const Camera& camera : rig.cameras) towards_cameras += camera.CenterInWorld() - centroid;
  if (normal.dot(towards_cameras) < 0.0) normal = -normal;
  WorldFrameFit fit;
  fit.new_from_old.rotation =
      Eigen::Quaterniond::FromTwoVectors(normal, Eigen::Vector3d::Unit(up_axis)).toRotationMatrix();
  fit.new_from_old.translation = -fit.new_from_old.rotation * centroid;
  double sum = 0.0;
  for (const Eigen::Vector3d& p : floor_points) {
    const double d = (p - centroid).dot(normal);
    sum += d * d;
  }
  fit.fit_rms_mm = std::sqrt(sum / static_cast<double>(floor_points.size()));
  fit.measured = floor_points;
  return fit;
}

Rig TransformRig(const Rig& rig, const SimilarityTransform& new_from_old) {
  Rig moved = rig;
  for (Camera& camera : moved.cameras) {
    const Eigen::Vector3d centre = new_from_old.Apply(camera.CenterInWorld());
    camera.rotation = camera.rotation * new_from_old.rotation.transpose();
    camera.translation = -camera.rotation * centre;
  }
  return moved;
}

}  // namespace mocap
