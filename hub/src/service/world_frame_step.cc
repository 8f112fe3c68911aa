// The world frame from a window of live frame sets: L-frame or floor, with a report for the console.
#include "service/world_frame_step.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Geometry>

#include "calib/world_frame.h"
#include "recon/reconstructor.h"
#include "service/api_error.h"

namespace mocap::service {
namespace {

constexpr double kDegPerRad = 180.0 / M_PI;

nlohmann::json Vec(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

const char* AxisName(int axis) { return axis == 0 ? "x" : axis == 1 ? "y" : "z"; }

// Every frame set's reconstructed points (no predictions: the markers lie still anyway).
std::vector<std::vector<Eigen::Vector3d>> Reconstruct(const std::vector<FrameSet>& frames, const Rig& rig) {
  ReconstructorOptions options;
  options.use_predictions = false;
  Reconstructor reconstructor(rig, options);
  std::vector<ReconstructedPoint> points;
  std::vector<std::vector<Eigen::Vector3d>> out;
  for (const FrameSet& set : frames) {
    reconstructor.Process(set, {}, &points);
    out.emplace_back();
    for (const ReconstructedPoint& p : points) out.back().push_back(p.point_in_world);
  }
  return out;
}

size_t MedianCount(const std::vector<std::vector<Eigen::Vector3d>>& points) {
  if (points.empty()) return 0;
  std::vector<size_t> counts;
  for (const auto& frame : points) counts.push_back(frame.size());
  std::nth_element(counts.begin(), counts.begin() + counts.size() / 2, counts.end());
  return counts[counts.size() / 2];
}

// What the operator can change when the L-frame is not found, from what was seen.
std::string SeenAdvice(size_t seen, size_t wanted) {
  if (seen == 0) return "no marker was reconstructed: is the L-frame in view of at least two cameras, the nodes running?";
  if (seen < wanted)
    return std::to_string(seen) + " of its " + std::to_string(wanted) +
           " markers reconstructed (median per frame set): every marker must be seen by two or more cameras";
  if (seen > wanted)
    return std::to_string(seen) + " points reconstructed per frame set (median), more than its " +
           std::to_string(wanted) + " markers: take other markers out of view, or the geometry differs";
  return std::to_string(seen) + " points reconstructed per frame set (median) but not in its geometry: check the "
         "L-frame's dimensions and that it lies still";
}

}  // namespace

void WorldFrameRequest::Check() const {
  if (method != kWorldMethodLFrame && method != kWorldMethodFloor)
    throw ApiError(400, "'method' must be lframe or floor, not '" + method + "'");
  if (frames < 10 || frames > 2000) throw ApiError(400, "'frames' must be within 10..2000");
  if (up_axis < 0 || up_axis > 2) throw ApiError(400, "'up' must be x, y or z");
  if (!(max_fit_rms_mm > 0.0 && max_fit_rms_mm <= 100.0)) throw ApiError(400, "'max_fit_rms_mm' must be within 0..100");
  if (min_frames < 1 || min_frames > frames) throw ApiError(400, "'min_frames' must be within 1..frames");
  if (!lframe.empty() && method != kWorldMethodLFrame) throw ApiError(400, "'lframe' goes with method lframe only");
  if (!lframe.empty() && (lframe.size() < 3 || lframe.size() > 8))
    throw ApiError(400, "'lframe' must list 3..8 markers");
  for (const Eigen::Vector3d& p : lframe)
    if (!p.allFinite() || p.cwiseAbs().maxCoeff() > 1e5) throw ApiError(400, "'lframe' markers must be finite, mm, within 100 m");
}

WorldFrameSolution SolveWorldFrame(const std::vector<FrameSet>& frames, const Rig& rig,
                                   const WorldFrameRequest& request) {
  request.Check();
  const std::vector<std::vector<Eigen::Vector3d>> points = Reconstruct(frames, rig);
  const size_t seen = MedianCount(points);
  WorldFrameFit fit;
  std::vector<Eigen::Vector3d> model;
  const bool lframe = request.method == kWorldMethodLFrame;
  try {
    if (lframe) {
      model = request.lframe.empty() ? DefaultLFrame(request.up_axis) : request.lframe;
      LFrameOptions options;
      options.max_fit_rms_mm = request.max_fit_rms_mm;
      options.min_frames = request.min_frames;
      fit = LocateLFrame(frames, rig, model, options);
    } else {
      std::vector<Eigen::Vector3d> floor;
      for (const auto& frame : points) floor.insert(floor.end(), frame.begin(), frame.end());
      fit = LevelOnFloor(floor, rig, request.up_axis);
      fit.frames_used = static_cast<int>(frames.size());
      fit.measured = points.back();  // what the last frame set saw (LevelOnFloor had points)
    }
  } catch (const std::invalid_argument& e) {
    if (lframe) throw ApiError(400, std::string("'lframe': ") + e.what());
    throw ApiError(422, std::string("the floor was not found: ") + e.what() + " (" +
                            std::to_string(seen) + " points reconstructed per frame set, median)");
  } catch (const std::runtime_error& e) {
    throw ApiError(422, std::string(e.what()) + "; " + SeenAdvice(seen, model.size()));
  }
  const SimilarityTransform& t = fit.new_from_old;
  const Eigen::Vector3d up = Eigen::Vector3d::Unit(request.up_axis);
  const Eigen::Vector3d new_up_in_old = t.rotation.transpose() * up;
  nlohmann::json markers = nlohmann::json::array();
  for (size_t k = 0; k < fit.measured.size(); ++k) {
    const Eigen::Vector3d measured = t.Apply(fit.measured[k]);
    if (lframe) {
      markers.push_back({{"model", Vec(model[k])}, {"measured", Vec(measured)}, {"error_mm", (measured - model[k]).norm()}});
    } else {
      markers.push_back({{"model", nullptr}, {"measured", Vec(measured)}, {"error_mm", nullptr}});
    }
  }
  WorldFrameSolution solution;
  solution.rig = TransformRig(rig, t);
  solution.report = {
      {"method", request.method},
      {"up", AxisName(request.up_axis)},
      {"frames", frames.size()},
      {"frames_used", fit.frames_used},
      {"points_per_frame", seen},
      {"markers", markers},
      {"fit_rms_mm", fit.fit_rms_mm},
      {"moved_mm", t.translation.norm()},
      {"turned_deg", Eigen::AngleAxisd(t.rotation).angle() * kDegPerRad},
      {"tilt_removed_deg", std::acos(std::clamp(new_up_in_old.dot(up), -1.0, 1.0)) * kDegPerRad},
      {"axes", {{"x", Vec(t.rotation.row(0).transpose())}, {"y", Vec(t.rotation.row(1).transpose())},
                {"z", Vec(t.rotation.row(2).transpose())}}}};
  return solution;
}

}  // namespace mocap::service
