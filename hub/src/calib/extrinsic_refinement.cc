// Continuous calibration's solve: detect, resect each moved camera, refine jointly, accept.
#include "calib/extrinsic_refinement.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

#include <ceres/loss_function.h>
#include <ceres/problem.h>
#include <ceres/solver.h>

#include <Eigen/Geometry>

#include "calib/camera_blocks.h"
#include "calib/cost_functions.h"
#include "calib/marker_reprojection_error.h"
#include "geometry/triangulation.h"

namespace mocap {

void ExtrinsicRefinementOptions::Check() const {
  detection.Check();
  relocalization.Check();
  if (!(loss_scale_px > 0.0) || !std::isfinite(loss_scale_px)) throw std::invalid_argument("loss_scale_px must be > 0");
  if (!(outlier_px > 0.0) || !std::isfinite(outlier_px)) throw std::invalid_argument("outlier_px must be > 0");
  if (max_points < 10) throw std::invalid_argument("max_points must be >= 10");
  if (!(min_improvement >= 1.0) || !std::isfinite(min_improvement))
    throw std::invalid_argument("min_improvement must be >= 1");
  if (max_iterations < 1) throw std::invalid_argument("max_iterations must be >= 1");
  if (num_threads < 1) throw std::invalid_argument("num_threads must be >= 1");
}

bool ExtrinsicRefinement::Changed() const {
  for (const CameraRefinement& c : cameras) {
    if (c.accepted) return true;
  }
  return false;
}

namespace {

double Median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

// max(floor, 5 robust sigma) of residual lengths: 1.4826 x median is sigma for a Gaussian
// per-coordinate spread only roughly (lengths are Rayleigh), which is what a gate needs.
double OutlierGate(const std::vector<double>& lengths, double floor_px) {
  return std::max(floor_px, 5.0 * 1.4826 * Median(lengths));
}

ceres::Solver::Options SolverOptions(const ExtrinsicRefinementOptions& options) {
  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::DENSE_SCHUR;
  solver.max_num_iterations = options.max_iterations;
  solver.num_threads = options.num_threads;
  solver.function_tolerance = 1e-12;
  solver.gradient_tolerance = 1e-14;
  solver.parameter_tolerance = 1e-12;
  solver.logging_type = ceres::SILENT;
  return solver;
}

class ExtrinsicRefiner {
 public:
  ExtrinsicRefiner(const Rig& rig, const std::deque<MarkerSample>& samples, const std::deque<FrameBlobs>& blobs,
                   const ExtrinsicRefinementOptions& options)
      : rig_(rig),
        samples_(samples),
        blobs_(blobs),
        options_(options),
        moved_(rig.cameras.size(), 0),
        lost_(rig.cameras.size(), 0) {}

  ExtrinsicRefinement Run() {
    ExtrinsicRefinement result;
    result.rig = rig_;
    result.samples = samples_.size();
    const BumpDetection before = DetectBumps(ComputeCameraResiduals(rig_, samples_), options_.detection);
    result.baseline_px = before.baseline_px;
    size_t moved = 0;
    for (size_t c = 0; c < rig_.cameras.size(); ++c) {
      CameraRefinement camera;
      camera.camera_id = rig_.cameras[c].id;
      camera.state_before = before.cameras[c].state;
      camera.before = before.cameras[c].residuals;
      camera.after = camera.before;
      camera.state_after = camera.state_before;
      result.cameras.push_back(camera);
      const CameraPoseState s = camera.state_before;
      if (s == CameraPoseState::kBumped || (options_.refine_drifting && s == CameraPoseState::kDrifting)) {
        moved_[c] = 1;
        ++moved;
      }
    }
    if (moved == 0) return result;
    const size_t held = rig_.cameras.size() - moved;
    if (held < 2)
      throw std::runtime_error(std::to_string(moved) + " of " + std::to_string(rig_.cameras.size()) +
                               " cameras moved: too few are left to hold the scale and world frame; "
                               "calibrate with the wand again");
    solved_ = rig_;
    repaired_ = samples_;
    for (size_t c = 0; c < rig_.cameras.size(); ++c) {
      if (moved_[c]) Relocate(c, &result.cameras[c]);
    }
    result.points_solved = SolveJointly(&result);
    Accept(before, &result);
    return result;
  }

 private:
  // Finds the moved camera again from its blobs (not from the old pose), then pairs its views
  // anew under the found pose: the old pose's nearest blobs leave every sample, and each
  // sample's point, triangulated by the held cameras, takes the camera's unambiguous nearest
  // blob within the gate.
  void Relocate(size_t camera, CameraRefinement* refinement) {
    refinement->relocalization =
        RelocalizeCamera(rig_, camera, moved_, samples_, blobs_, options_.relocalization);
    if (!refinement->relocalization.ok) {
      lost_[camera] = 1;
      return;
    }
    solved_.cameras[camera] = refinement->relocalization.camera;
    const double gate = std::max(refinement->relocalization.gate_px, 3.0 * options_.outlier_px);
    const Camera& pose = solved_.cameras[camera];
    size_t next_blobs = 0;
    for (MarkerSample& sample : repaired_) {
      sample.views.erase(std::remove_if(sample.views.begin(), sample.views.end(),
                                        [&](const MarkerView& view) { return view.camera == static_cast<int>(camera); }),
                         sample.views.end());
      while (next_blobs < blobs_.size() && blobs_[next_blobs].frame < sample.frame) ++next_blobs;
      if (next_blobs == blobs_.size() || blobs_[next_blobs].frame != sample.frame) continue;
      const std::vector<Eigen::Vector2d>& blobs = blobs_[next_blobs].pixels[camera];
      Eigen::Vector3d point;
      Eigen::Vector2d projected;
      if (blobs.empty() || !LeaveOneOutPoint(rig_, sample, -1, moved_, &point) ||
          !pose.ProjectToPixel(point, &projected) || !pose.InImage(projected))
        continue;
      const int blob = UnambiguousNearestBlob(blobs, projected, gate, options_.relocalization.ambiguity_ratio);
      if (blob < 0) continue;
      MarkerView view;
      view.camera = static_cast<int>(camera);
      view.pixel = blobs[static_cast<size_t>(blob)];
      view.normalized = pose.UndistortPixel(view.pixel);
      view.reconstructed = false;
      sample.views.push_back(view);
    }
  }

  struct JointPoint {
    std::array<double, 3> position{};
    std::vector<const MarkerView*> views;
  };

  // Views a joint point keeps: the held cameras' reconstructed views, and the moved cameras'
  // views within the gate of their resected pose.
  std::vector<JointPoint> GatherPoints() const {
    std::vector<JointPoint> points;
    const size_t stride = std::max<size_t>(1, (repaired_.size() + options_.max_points - 1) / options_.max_points);
    for (size_t s = 0; s < repaired_.size(); s += stride) {
      const MarkerSample& sample = repaired_[s];
      JointPoint point;
      std::vector<PointView> views;
      for (const MarkerView& view : sample.views) {
        if (lost_[view.camera] || (!moved_[view.camera] && !view.reconstructed)) continue;
        point.views.push_back(&view);
        views.push_back(ViewThrough(solved_.cameras[view.camera], view.normalized));
      }
      Eigen::Vector3d position;
      if (views.size() < 2 || !TriangulatePoint(views, &position)) continue;
      // Moved cameras' views far from the point (a wrong pairing) do not enter.
      std::vector<const MarkerView*> kept;
      for (const MarkerView* view : point.views) {
        Eigen::Vector2d projected;
        if (!solved_.cameras[view->camera].ProjectToPixel(position, &projected)) continue;
        if (moved_[view->camera] && (projected - view->pixel).norm() > 3.0 * options_.outlier_px) continue;
        kept.push_back(view);
      }
      if (kept.size() < 2) continue;
      point.views = std::move(kept);
      point.position = {position.x(), position.y(), position.z()};
      points.push_back(std::move(point));
    }
    return points;
  }

  size_t SolveJointly(ExtrinsicRefinement* result) {
    std::vector<JointPoint> points = GatherPoints();
    const size_t n = rig_.cameras.size();
    std::vector<std::array<double, kPoseSize>> poses(n);
    std::vector<std::array<double, kIntrinsicsSize>> intrinsics(n);
    for (size_t c = 0; c < n; ++c) {
      poses[c] = PoseBlock(solved_.cameras[c]);
      intrinsics[c] = IntrinsicsBlock(solved_.cameras[c].intrinsics);
    }
    // Per point and view: still in the solve.
    std::vector<std::vector<char>> active(points.size());
    for (size_t p = 0; p < points.size(); ++p) active[p].assign(points[p].views.size(), 1);
    const std::unique_ptr<ceres::LossFunction> loss(new ceres::HuberLoss(options_.loss_scale_px));
    for (int pass = 0; pass < 2; ++pass) {
      ceres::Problem::Options problem_options;
      problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
      ceres::Problem problem(problem_options);
      std::vector<char> in_problem(n, 0);
      for (size_t p = 0; p < points.size(); ++p) {
        for (size_t v = 0; v < points[p].views.size(); ++v) {
          if (!active[p][v]) continue;
          const MarkerView& view = *points[p].views[v];
          problem.AddResidualBlock(MarkerReprojectionError::Create(view.pixel), loss.get(), poses[view.camera].data(),
                                   intrinsics[view.camera].data(), points[p].position.data());
          in_problem[view.camera] = 1;
        }
      }
      for (size_t c = 0; c < n; ++c) {
        if (!in_problem[c]) continue;
        problem.SetParameterBlockConstant(intrinsics[c].data());
        if (!moved_[c]) problem.SetParameterBlockConstant(poses[c].data());
      }
      ceres::Solver::Summary summary;
      ceres::Solve(SolverOptions(options_), &problem, &summary);
      for (size_t c = 0; c < n; ++c) {
        if (moved_[c]) SetPoseFromBlock(poses[c].data(), &solved_.cameras[c]);
      }
      DropOutliers(points, &active);
    }
    for (size_t c = 0; c < n; ++c) {
      if (!moved_[c]) continue;
      CameraRefinement& camera = result->cameras[c];
      for (size_t p = 0; p < points.size(); ++p) {
        for (size_t v = 0; v < points[p].views.size(); ++v) {
          if (points[p].views[v]->camera != static_cast<int>(c)) continue;
          (active[p][v] ? camera.inlier_views : camera.outlier_views) += 1;
        }
      }
    }
    return points.size();
  }

  // A moved camera's view beyond its gate leaves the solve; so does any view beyond a wide gate.
  void DropOutliers(const std::vector<JointPoint>& points, std::vector<std::vector<char>>* active) const {
    const size_t n = rig_.cameras.size();
    std::vector<std::vector<double>> lengths(n);
    std::vector<std::vector<double>> errors(points.size());
    for (size_t p = 0; p < points.size(); ++p) {
      const Eigen::Vector3d position(points[p].position[0], points[p].position[1], points[p].position[2]);
      errors[p].assign(points[p].views.size(), 1e9);
      for (size_t v = 0; v < points[p].views.size(); ++v) {
        const MarkerView& view = *points[p].views[v];
        Eigen::Vector2d projected;
        if (!solved_.cameras[view.camera].ProjectToPixel(position, &projected)) continue;
        errors[p][v] = (projected - view.pixel).norm();
        if ((*active)[p][v]) lengths[view.camera].push_back(errors[p][v]);
      }
    }
    std::vector<double> gate(n);
    for (size_t c = 0; c < n; ++c) gate[c] = OutlierGate(lengths[c], options_.outlier_px);
    for (size_t p = 0; p < points.size(); ++p) {
      for (size_t v = 0; v < points[p].views.size(); ++v) {
        (*active)[p][v] = errors[p][v] <= gate[points[p].views[v]->camera];
      }
    }
  }

  // Each moved camera keeps its solved pose only when its residuals (of its views paired anew)
  // came back to the rig's level by a clear factor: otherwise the old pose stays and the report
  // says why.
  void Accept(const BumpDetection& before, ExtrinsicRefinement* result) {
    const BumpDetection after = DetectBumps(ComputeCameraResiduals(solved_, repaired_), options_.detection);
    for (size_t c = 0; c < rig_.cameras.size(); ++c) {
      if (!moved_[c]) continue;
      CameraRefinement& camera = result->cameras[c];
      camera.refined = true;
      const Camera& old_pose = rig_.cameras[c];
      const Camera& new_pose = solved_.cameras[c];
      camera.centre_change_mm = (old_pose.CenterInWorld() - new_pose.CenterInWorld()).norm();
      camera.rotation_change_deg =
          std::abs(Eigen::AngleAxisd(old_pose.rotation * new_pose.rotation.transpose()).angle()) * 180.0 / M_PI;
      const CameraResiduals& was = before.cameras[c].residuals;
      const CameraResiduals& now = after.cameras[c].residuals;
      if (lost_[c]) {
        camera.note = camera.relocalization.reason;
      } else if (after.cameras[c].state != CameraPoseState::kOk) {
        camera.note = std::string("residuals still ") + CameraPoseStateName(after.cameras[c].state) +
                      " after the solve (median " + std::to_string(now.median_px) +
                      " px); capture longer with the subject in its view, or calibrate with the wand again";
      } else if (!(now.median_px * options_.min_improvement <= was.median_px)) {
        camera.note = "the solve did not lower the median residual by the required factor (the camera may not "
                      "have moved: keep the calibration, or set --baseline-px to the calibration's residual)";
      } else {
        camera.accepted = true;
        result->rig.cameras[c] = new_pose;
      }
    }
    const BumpDetection final_detection = DetectBumps(ComputeCameraResiduals(result->rig, repaired_), options_.detection);
    for (size_t c = 0; c < rig_.cameras.size(); ++c) {
      result->cameras[c].after = final_detection.cameras[c].residuals;
      result->cameras[c].state_after = final_detection.cameras[c].state;
    }
  }

  const Rig& rig_;
  const std::deque<MarkerSample>& samples_;
  const std::deque<FrameBlobs>& blobs_;
  const ExtrinsicRefinementOptions& options_;
  std::vector<char> moved_;
  std::vector<char> lost_;             // moved cameras that could not be found again
  Rig solved_;
  std::deque<MarkerSample> repaired_;  // the samples with the moved cameras' views paired anew
};

}  // namespace

ExtrinsicRefinement RefineExtrinsics(const Rig& rig, const std::deque<MarkerSample>& samples,
                                     const std::deque<FrameBlobs>& blobs, const ExtrinsicRefinementOptions& options) {
  options.Check();
  return ExtrinsicRefiner(rig, samples, blobs, options).Run();
}

}  // namespace mocap
