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

// True when the worst view, though within the absolute limit, stands out from the others: its
// error against the point the other views make alone is over outlier_ratio times their median
// error. That is a blob biased by another marker (two markers projecting a pixel or two apart
// make one round blob, which the node's shape test cannot flag) that, kept, pulls the point by
// its share; the fewer the views, the larger that share. With four or more views only, so that
// three remain to judge; cheap when the worst error is under outlier_floor_px.
bool StandsOut(const RigModel& rig, const FrameViews& views, const std::vector<int>& observations,
               const Eigen::Vector3d& point, const std::vector<double>& errors_px, size_t worst,
               const TriangulationOptions& options) {
  if (observations.size() < 4 || !(errors_px[worst] > options.outlier_floor_px)) return false;
  thread_local std::vector<double> errors;
  // Cheap gate first, for points of many views: the others' median error at the point of all
  // views. A biased view pulls the point by about its error over the number of views, so with
  // ten or more the others' median there is within a small part of a pixel of theirs without it,
  // and one 25 % over the precision limit does not come under it. Points of noisy cameras (most,
  // at 0.2 px) stop here instead of paying a second solve; with fewer views the pull is larger
  // (a 1 px bias moves four views' errors by ~0.25 px) and the full test runs.
  constexpr size_t kGateViews = 10;
  const double precise_px = options.precise_fraction * options.max_reprojection_px;
  if (observations.size() >= kGateViews) {
    // The others' median (element others / 2 in sorted order) is under the gate exactly when
    // more than others / 2 of them are: a count instead of a selection, the same answer.
    const size_t others = errors_px.size() - 1;
    const double gate_px = PreciseGatePx(options);
    size_t under = 0;
    for (size_t i = 0; i < errors_px.size(); ++i) under += i != worst && errors_px[i] < gate_px;
    if (!(under > others / 2)) return false;
  }
  thread_local std::vector<int> others;
  others.clear();
  for (size_t i = 0; i < observations.size(); ++i) {
    if (i != worst) others.push_back(observations[i]);
  }
  Eigen::Vector3d alone = point;
  if (!RefinePoint(rig, views, others, options.refine_iterations, &alone)) return false;
  ReprojectionErrors(rig, views, others, alone, &errors);
  std::nth_element(errors.begin(), errors.begin() + static_cast<std::ptrdiff_t>(errors.size() / 2), errors.end());
  const double median_px = errors[errors.size() / 2];
  if (!(median_px < precise_px)) return false;
  const Observation& obs = views.observations[observations[worst]];
  const CameraModel& cam = rig.camera(obs.camera);
  const Eigen::Vector3d p = cam.cam_from_world_rotation * alone + cam.cam_from_world_translation;
  const double own_px = p.z() > 1e-9 ? cam.focal_px * (p.head<2>() / p.z() - obs.normalized).norm() : HUGE_VAL;
  return own_px > options.outlier_ratio * median_px;
}

// Adds the views set aside to the solved point as members when within max_merged_px of it (so
// that they cannot seed a ghost), to its rejected views otherwise.
void TakeBackAside(const RigModel& rig, const FrameViews& views, const std::vector<int>& aside,
                   const TriangulationOptions& options, TriangulatedPoint* result) {
  if (aside.empty()) return;
  thread_local std::vector<double> errors;
  ReprojectionErrors(rig, views, aside, result->point_in_world, &errors);
  for (size_t i = 0; i < aside.size(); ++i) {
    (errors[i] <= options.MergedLimitPx() ? result->observations : result->rejected).push_back(aside[i]);
  }
}

// Solve, then drop the worst view while its residual is over the limit (or it stands out) and
// three or more remain. Works on result->observations in place (its capacity is reused from call
// to call); appends dropped views to result->rejected.
bool SolveDroppingOutliers(const RigModel& rig, const FrameViews& views, const TriangulationOptions& options,
                           TriangulatedPoint* result) {
  // Per-thread scratch: the per-frame hot path allocates nothing once warmed up.
  thread_local std::vector<double> errors;
  // Views that stood out: left out of the solve, then members of the point as a merged blob is.
  thread_local std::vector<int> aside;
  aside.clear();
  std::vector<int>& observations = result->observations;
  while (static_cast<int>(observations.size()) >= options.min_views) {
    Eigen::Vector3d point;
    if (!TriangulateLinear(rig, views, observations, &point)) return false;
    if (!RefinePoint(rig, views, observations, options.refine_iterations, &point)) return false;
    ReprojectionErrors(rig, views, observations, point, &errors);
    const auto worst = std::max_element(errors.begin(), errors.end());
    const size_t worst_index = static_cast<size_t>(worst - errors.begin());
    const bool in_front = InFrontOfAll(rig, views, observations, point, options.min_depth_mm);
    const bool within = *worst <= options.max_reprojection_px && in_front;
    const bool stands_out = within && StandsOut(rig, views, observations, point, errors, worst_index, options);
    if (within && !stands_out) {
      double sum_squares = 0.0;
      for (double e : errors) sum_squares += e * e;
      result->point_in_world = point;
      result->rms_px = std::sqrt(sum_squares / errors.size());
      result->max_px = *worst;
      TakeBackAside(rig, views, aside, options, result);
      return true;
    }
    // With two views a large residual cannot say which view is wrong: give up.
    if (observations.size() <= 2) return false;
    (stands_out ? aside : result->rejected).push_back(observations[worst_index]);
    observations.erase(observations.begin() + static_cast<std::ptrdiff_t>(worst_index));
  }
  return false;
}

// Solves without the views `set_aside` picks when any and min_views others remain; the views set
// aside then stay members of the point when within max_merged_px of it. With a non-zero
// max_rms_px, the point of the other views must also be that precise. False: not so solved.
template <typename SetAside>
bool SolveSettingAside(const RigModel& rig, const FrameViews& views, const std::vector<int>& observations,
                       const TriangulationOptions& options, double max_rms_px, SetAside set_aside,
                       TriangulatedPoint* result) {
  thread_local std::vector<int> aside;
  aside.clear();
  result->observations.clear();
  result->rejected.clear();
  for (int index : observations) (set_aside(index) ? aside : result->observations).push_back(index);
  if (aside.empty() || static_cast<int>(result->observations.size()) < options.min_views) return false;
  if (!SolveDroppingOutliers(rig, views, options, result) || (max_rms_px > 0.0 && !(result->rms_px < max_rms_px))) {
    result->rejected.clear();
    return false;
  }
  TakeBackAside(rig, views, aside, options, result);
  return true;
}

}  // namespace

bool TriangulateRobust(const RigModel& rig, const FrameViews& views, const std::vector<int>& observations,
                       const TriangulationOptions& options, TriangulatedPoint* result,
                       const std::vector<char>* shared) {
  thread_local std::vector<int> input;
  // The caller may hand over the result's own views: keep a copy before overwriting them.
  const std::vector<int>* given = &observations;
  if (given == &result->observations) {
    input = observations;
    given = &input;
  }
  const auto merged = [&](int index) { return (views.observations[index].flags & kBlobMerged) != 0; };
  // A blob two predictions share (its centroid off for both markers) is set aside as a merged
  // one, but only when the other views alone make a precise point: a noisy point keeps it.
  if (shared != nullptr &&
      SolveSettingAside(rig, views, *given, options, options.precise_fraction * options.max_reprojection_px,
                        [&](int index) { return merged(index) || (*shared)[static_cast<size_t>(index)] != 0; },
                        result)) {
    return true;
  }
  // A merged blob's centroid lies between its markers and measures neither: with enough other
  // views the point is solved without it, and it stays a member (so it cannot start a ghost)
  // when it lies within a marker's radius or so of the solution.
  if (SolveSettingAside(rig, views, *given, options, 0.0, merged, result)) return true;
  result->rejected.clear();
  result->observations.assign(given->begin(), given->end());
  return SolveDroppingOutliers(rig, views, options, result);
}

}  // namespace mocap
