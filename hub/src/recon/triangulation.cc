// Recon's robust triangulation: the linear estimate and Gauss-Newton steps come from
// geometry/triangulation.h; outlier-view rejection and the pixel residual checks live here.
#include "recon/triangulation.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "geometry/triangulation.h"
#include "ingest/camera_frame.h"

namespace mocap {

bool TriangulateLinear(const RigModel& rig, const FrameViews& views,
                       const std::vector<int>& observations, Eigen::Vector3d* point_in_world) {
  LinearTriangulation linear;
  for (int index : observations) {
    const Observation& obs = views.observations[index];
    const CameraModel& cam = rig.camera(obs.camera);
    linear.AddView(cam.cam_from_world_rotation, cam.cam_from_world_translation, obs.normalized);
  }
  return linear.Solve(point_in_world);
}

bool RefinePoint(const RigModel& rig, const FrameViews& views, const std::vector<int>& observations,
                 int iterations, Eigen::Vector3d* point_in_world) {
  Eigen::Vector3d point = *point_in_world;
  for (int iteration = 0; iteration < iterations; ++iteration) {
    GaussNewtonTriangulationStep gauss_newton(point);
    for (int index : observations) {
      const Observation& obs = views.observations[index];
      const CameraModel& cam = rig.camera(obs.camera);
      // Weighting by the focal length makes the error pixels, the unit of the outlier test.
      if (!gauss_newton.AddView(cam.cam_from_world_rotation, cam.cam_from_world_translation, obs.normalized,
                                cam.focal_px)) {
        return false;
      }
    }
    Eigen::Vector3d step;
    if (!gauss_newton.Solve(&step)) return false;
    point -= step;
    // Steps under a micrometre change nothing measurable; stop early to save time.
    if (step.squaredNorm() < 1e-2) break;
  }
  *point_in_world = point;
  return true;
}

void ReprojectionErrors(const RigModel& rig, const FrameViews& views,
                        const std::vector<int>& observations, const Eigen::Vector3d& point_in_world,
                        std::vector<double>* errors_px) {
  errors_px->resize(observations.size());
  for (size_t i = 0; i < observations.size(); ++i) {
    const Observation& obs = views.observations[observations[i]];
    const CameraModel& cam = rig.camera(obs.camera);
    const Eigen::Vector3d p =
        cam.cam_from_world_rotation * point_in_world + cam.cam_from_world_translation;
    if (!(p.z() > 1e-9)) {
      (*errors_px)[i] = HUGE_VAL;
      continue;
    }
    (*errors_px)[i] = cam.focal_px * (p.head<2>() / p.z() - obs.normalized).norm();
  }
}

namespace {

bool InFrontOfAll(const RigModel& rig, const FrameViews& views, const std::vector<int>& observations,
                  const Eigen::Vector3d& point, double min_depth_mm) {
  for (int index : observations) {
    const CameraModel& cam = rig.camera(views.observations[index].camera);
    const double depth =
        cam.cam_from_world_rotation.row(2).dot(point) + cam.cam_from_world_translation.z();
    if (depth < min_depth_mm) return false;
  }
  return true;
}

// Solve, then drop the worst view while its residual is over the limit and three or more remain.
// Works on result->observations in place (its capacity is reused from call to call); appends
// dropped views to result->rejected.
bool SolveDroppingOutliers(const RigModel& rig, const FrameViews& views, const TriangulationOptions& options,
                           TriangulatedPoint* result) {
  // Per-thread scratch: the per-frame hot path allocates nothing once warmed up.
  thread_local std::vector<double> errors;
  std::vector<int>& observations = result->observations;
  while (static_cast<int>(observations.size()) >= options.min_views) {
    Eigen::Vector3d point;
    if (!TriangulateLinear(rig, views, observations, &point)) return false;
    if (!RefinePoint(rig, views, observations, options.refine_iterations, &point)) return false;
    ReprojectionErrors(rig, views, observations, point, &errors);
    const auto worst = std::max_element(errors.begin(), errors.end());
    const bool in_front = InFrontOfAll(rig, views, observations, point, options.min_depth_mm);
    if (*worst <= options.max_reprojection_px && in_front) {
      double sum_squares = 0.0;
      for (double e : errors) sum_squares += e * e;
      result->point_in_world = point;
      result->rms_px = std::sqrt(sum_squares / errors.size());
      result->max_px = *worst;
      return true;
    }
    // With two views a large residual cannot say which view is wrong: give up.
    if (observations.size() <= 2) return false;
    const size_t drop = static_cast<size_t>(worst - errors.begin());
    result->rejected.push_back(observations[drop]);
    observations.erase(observations.begin() + static_cast<std::ptrdiff_t>(drop));
  }
  return false;
}

}  // namespace

bool TriangulateRobust(const RigModel& rig, const FrameViews& views, const std::vector<int>& observations,
                       const TriangulationOptions& options, TriangulatedPoint* result) {
  thread_local std::vector<int> merged, input;
  thread_local std::vector<double> errors;
  // The caller may hand over the result's own views: keep a copy before overwriting them.
  const std::vector<int>* given = &observations;
  if (given == &result->observations) {
    input = observations;
    given = &input;
  }
  result->rejected.clear();
  result->observations.clear();
  merged.clear();
  for (int index : *given) {
    if (views.observations[index].flags & kBlobMerged) {
      merged.push_back(index);
    } else {
      result->observations.push_back(index);
    }
  }
  // A merged blob's centroid lies between its markers and measures neither: with enough other
  // views the point is solved without it, and it stays a member (so it cannot start a ghost)
  // when it lies within a marker's radius or so of the solution.
  if (!merged.empty() && static_cast<int>(result->observations.size()) >= options.min_views &&
      SolveDroppingOutliers(rig, views, options, result)) {
    ReprojectionErrors(rig, views, merged, result->point_in_world, &errors);
    for (size_t i = 0; i < merged.size(); ++i) {
      (errors[i] <= options.max_merged_px ? result->observations : result->rejected).push_back(merged[i]);
    }
    return true;
  }
  result->rejected.clear();
  result->observations.assign(given->begin(), given->end());
  return SolveDroppingOutliers(rig, views, options, result);
}

}  // namespace mocap
