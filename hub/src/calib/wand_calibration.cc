// The wand calibration pipeline. Label resolution works in two regimes: before the first bundle
// the end markers are matched across cameras by epipolar distance under the initial poses;
// afterwards each view simply keeps the end order that reprojects better.
#include "calib/wand_calibration.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "calib/reprojection_sum.h"
#include "geometry/triangulation.h"

namespace mocap {
namespace {

// RMS over the view's markers of the reprojection error length (the hub's rms_px).
double ViewRmsPx(const Camera& camera, const WandView& view, const WandPose& pose, const WandGeometry& wand,
                 bool swapped) {
  const size_t last = view.pixels.size() - 1;
  double sum = 0.0;
  for (size_t k = 0; k <= last; ++k) {
    Eigen::Vector2d projected;
    if (!camera.ProjectToPixel(pose.Marker(wand, swapped ? last - k : k), &projected)) {
      return std::numeric_limits<double>::infinity();
    }
    sum += (projected - view.pixels[k]).squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(view.pixels.size()));
}

// Both ends of the wand from two views, the second view's ends swapped or not.
bool TriangulateEnds(const std::vector<Camera>& cameras, const WandView& a, const WandView& b, bool swap_b,
                     Eigen::Vector3d ends[2]) {
  const size_t last = a.normalized.size() - 1;
  for (int e = 0; e < 2; ++e) {
    const size_t k = e == 0 ? 0 : last;
    const size_t kb = swap_b ? last - k : k;
    if (!TriangulatePoint({{cameras[a.camera].ProjectionMatrix(), a.normalized[k]},
                            {cameras[b.camera].ProjectionMatrix(), b.normalized[kb]}},
                           &ends[e])) {
      return false;
    }
    if (!(cameras[a.camera].PointInCamera(ends[e]).z() > 0.0 && cameras[b.camera].PointInCamera(ends[e]).z() > 0.0)) {
      return false;
    }
  }
  return true;
}

// Labels a frame's views consistently and drops views that do not fit, robustly against a wrong
// view (a flicker blob standing in for a hidden marker): the seed is the pair of views whose
// triangulated wand length is closest to the true one; other views join, in the end order that
// reprojects better, when they reproject within gate_px of the seed wand. Returns false when no
// pair gives a plausible wand.
bool LabelFrameRobustly(const std::vector<Camera>& cameras, const WandGeometry& wand, double gate_px,
                        WandFrame* frame) {
  auto& views = frame->views;
  // Pairs among the first views only: enough to find a good seed, bounded cost per frame.
  const size_t considered = std::min<size_t>(views.size(), 6);
  double best_error = 0.1 * wand.LengthMm();
  size_t best_i = 0, best_j = 0;
  bool best_swap = false, found = false;
  for (size_t i = 0; i < considered; ++i) {
    for (size_t j = i + 1; j < considered; ++j) {
      for (bool swap : {false, true}) {
        Eigen::Vector3d ends[2];
        if (!TriangulateEnds(cameras, views[i], views[j], swap, ends)) continue;
        const double error = std::abs((ends[1] - ends[0]).norm() - wand.LengthMm());
        if (error < best_error) {
          best_error = error;
          best_i = i;
          best_j = j;
          best_swap = swap;
          found = true;
        }
      }
    }
  }
  if (!found) return false;
  if (best_swap) views[best_j].SwapEnds();
  Eigen::Vector3d ends[2];
  TriangulateEnds(cameras, views[best_i], views[best_j], false, ends);
  if (wand.MarkerCount() == 3) {
    // The off-centre middle marker tells the ends apart: if it sits where the model puts it
    // from the other end, the seed's end order is reversed.
    Eigen::Vector3d middle;
    if (TriangulatePoint({{cameras[views[best_i].camera].ProjectionMatrix(), views[best_i].normalized[1]},
                           {cameras[views[best_j].camera].ProjectionMatrix(), views[best_j].normalized[1]}},
                          &middle)) {
      const double from_first = (middle - ends[0]).norm();
      const double expected = wand.marker_offsets_mm[1] - wand.marker_offsets_mm[0];
      const double mirrored = wand.marker_offsets_mm[2] - wand.marker_offsets_mm[1];
      if (std::abs(from_first - mirrored) < std::abs(from_first - expected)) {
        views[best_i].SwapEnds();
        views[best_j].SwapEnds();
        std::swap(ends[0], ends[1]);
      }
    }
  }
  WandPose seed;
  seed.centre = 0.5 * (ends[0] + ends[1]);
  seed.axis = (ends[1] - ends[0]).normalized();
  std::vector<WandView> kept;
  for (size_t v = 0; v < views.size(); ++v) {
    if (v == best_i || v == best_j) {
      kept.push_back(std::move(views[v]));
      continue;
    }
    const Camera& camera = cameras[views[v].camera];
    const double straight = ViewRmsPx(camera, views[v], seed, wand, false);
    const double swapped = ViewRmsPx(camera, views[v], seed, wand, true);
    if (swapped < straight) views[v].SwapEnds();
    if (std::min(straight, swapped) <= gate_px) kept.push_back(std::move(views[v]));
  }
  views = std::move(kept);
  return true;
}

bool TriangulateWand(const std::vector<Camera>& cameras, const WandFrame& frame, const WandGeometry& wand,
                     WandPose* pose) {
  const size_t last = wand.MarkerCount() - 1;
  Eigen::Vector3d ends[2];
  for (int e = 0; e < 2; ++e) {
    const size_t k = e == 0 ? 0 : last;
    std::vector<PointView> views;
    for (const WandView& view : frame.views) {
      views.push_back({cameras[view.camera].ProjectionMatrix(), view.normalized[k]});
    }
    if (!TriangulatePoint(views, &ends[e])) return false;
  }
  const Eigen::Vector3d axis = ends[1] - ends[0];
  if (!(axis.norm() > 1e-6)) return false;
  pose->centre = 0.5 * (ends[0] + ends[1]);
  pose->axis = axis.normalized();
  return true;
}

// Per view: keep the better end order, then drop views above the gate and frames left with
// fewer than two views. Returns the number of views dropped.
size_t RelabelAndReject(const std::vector<Camera>& cameras, const WandGeometry& wand, double gate_px,
                        std::vector<WandFrame>* frames, std::vector<WandPose>* poses) {
  size_t dropped = 0;
  std::vector<WandFrame> kept_frames;
  std::vector<WandPose> kept_poses;
  for (size_t f = 0; f < frames->size(); ++f) {
    WandFrame& frame = (*frames)[f];
    const WandPose& pose = (*poses)[f];
    std::vector<WandView> kept;
    for (WandView& view : frame.views) {
      const Camera& camera = cameras[view.camera];
      const double straight = ViewRmsPx(camera, view, pose, wand, false);
      const double swapped = ViewRmsPx(camera, view, pose, wand, true);
      if (swapped < straight) view.SwapEnds();
      if (std::min(straight, swapped) <= gate_px) {
        kept.push_back(std::move(view));
      } else {
        ++dropped;
      }
    }
    if (kept.size() < 2) {
      dropped += kept.size();
      continue;
    }
    frame.views = std::move(kept);
    kept_frames.push_back(std::move(frame));
    kept_poses.push_back(pose);
  }
  *frames = std::move(kept_frames);
  *poses = std::move(kept_poses);
  return dropped;
}

// Robust residual scale (per coordinate) from the median absolute residual.
double RobustSigmaPx(const std::vector<Camera>& cameras, const WandGeometry& wand,
                     const std::vector<WandFrame>& frames, const std::vector<WandPose>& poses) {
  std::vector<double> magnitudes;
  for (size_t f = 0; f < frames.size(); ++f) {
    for (const WandView& view : frames[f].views) {
      for (size_t k = 0; k < view.pixels.size(); ++k) {
        Eigen::Vector2d projected;
        if (!cameras[view.camera].ProjectToPixel(poses[f].Marker(wand, k), &projected)) continue;
        const Eigen::Vector2d r = projected - view.pixels[k];
        magnitudes.push_back(std::abs(r.x()));
        magnitudes.push_back(std::abs(r.y()));
      }
    }
  }
  if (magnitudes.empty()) return 0.0;
  const size_t mid = magnitudes.size() / 2;
  std::nth_element(magnitudes.begin(), magnitudes.begin() + static_cast<long>(mid), magnitudes.end());
  return 1.4826 * magnitudes[mid];
}

using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The wand solver's stages over one shared state: the frames and wand poses still in use, the
// cameras still active, and the report being filled. Run() calls the stages in order.
class WandSolver {
 public:
  WandSolver(const Rig& intrinsics, const WandGeometry& wand, const WandCalibrationOptions& options)
      : intrinsics_(intrinsics), wand_(wand), options_(options), n_(intrinsics.cameras.size()), active_(n_, true) {
    result_.cameras.resize(n_);
    for (size_t i = 0; i < n_; ++i) result_.cameras[i].id = intrinsics_.cameras[i].id;
  }

  WandCalibrationResult Run(const std::vector<FrameSet>& frame_sets) {
    auto stage_start = Clock::now();
    SelectFrames(frame_sets);
    result_.select_seconds = SecondsSince(stage_start);
    stage_start = Clock::now();
    Initialise();
    result_.initialize_seconds = SecondsSince(stage_start);
    stage_start = Clock::now();
    BundleAdjust();
    result_.bundle_seconds = SecondsSince(stage_start);
    result_.frames_used = frames_.size();
    result_.reference_camera_id = intrinsics_.cameras[init_.reference_camera].id;
    const std::vector<size_t> refused = Evaluate();
    if (!refused.empty()) {
      SolveWithout(refused);
      result_.bundle_seconds = SecondsSince(stage_start);
    }
    return std::move(result_);
  }

 private:
  // Wand frames seen by two or more cameras with enough views; the others are refused up front,
  // because cameras with too few wand views would only destabilise the solve.
  void SelectFrames(const std::vector<FrameSet>& frame_sets) {
    WandSelectionStats selection;
    frames_ = SelectWandFrames(frame_sets, intrinsics_, wand_, options_.selection, &selection);
    result_.frames_in = selection.frames_in;
    result_.frames_selected = selection.frames_selected;
    for (size_t i = 0; i < n_; ++i) result_.cameras[i].views_selected = selection.views_selected[i];
    for (size_t i = 0; i < n_; ++i) {
      if (static_cast<int>(result_.cameras[i].views_selected) < options_.min_views_per_camera) {
        active_[i] = false;
        result_.cameras[i].reason = "only " + std::to_string(result_.cameras[i].views_selected) +
                                    " frames show exactly the wand (need " +
                                    std::to_string(options_.min_views_per_camera) +
                                    "): wave the wand more in camera " + std::to_string(intrinsics_.cameras[i].id) +
                                    "'s view, away from other bright spots";
      }
    }
    DropInactiveViews();
    if (frames_.empty()) {
      throw std::runtime_error("no frame shows the wand (exactly " + std::to_string(wand_.MarkerCount()) +
                               " blobs) in two calibratable cameras: check the wand length, the marker count and "
                               "that other bright spots are out of view");
    }
  }

  // Keeps only the views of active cameras, and the frames that still have two of them.
  void DropInactiveViews() {
    std::vector<WandFrame> kept;
    for (WandFrame& frame : frames_) {
      frame.views.erase(std::remove_if(frame.views.begin(), frame.views.end(),
                                       [&](const WandView& v) { return !active_[v.camera]; }),
                        frame.views.end());
      if (frame.views.size() >= 2) kept.push_back(std::move(frame));
    }
    frames_ = std::move(kept);
  }

  // Relative poses from essential matrices, then labelled wand ends and first wand poses.
  void Initialise() {
    init_ = InitializeWandPoses(frames_, intrinsics_, wand_, options_.initialization);
    cameras_ = init_.cameras;
    for (size_t i = 0; i < n_; ++i) {
      if (active_[i] && !init_.posed[i]) {
        active_[i] = false;
        result_.cameras[i].reason = "could not be placed relative to the other cameras (" + init_.unposed_reason[i] +
                                    "): wave the wand where camera " + std::to_string(intrinsics_.cameras[i].id) +
                                    " and its neighbours see it together";
      }
    }
    DropInactiveViews();

    // Initial labels and wand poses.
    std::vector<WandFrame> labelled;
    for (WandFrame& frame : frames_) {
      if (!LabelFrameRobustly(cameras_, wand_, options_.initial_gate_px, &frame)) continue;
      WandPose pose;
      if (!TriangulateWand(cameras_, frame, wand_, &pose)) continue;
      labelled.push_back(std::move(frame));
      poses_.push_back(pose);
    }
    frames_ = std::move(labelled);
    RelabelAndReject(cameras_, wand_, options_.initial_gate_px, &frames_, &poses_);
    // Rejection may leave a camera without views; it then cannot be solved.
    RefuseUnseen();
    bundle_ = options_.bundle;
    bundle_.fixed_camera = init_.reference_camera;
  }

  // Refuses the active cameras left without any view.
  void RefuseUnseen() {
    std::vector<size_t> count(n_, 0);
    for (const WandFrame& frame : frames_) {
      for (const WandView& view : frame.views) ++count[view.camera];
    }
    for (size_t i = 0; i < n_; ++i) {
      if (active_[i] && count[i] == 0) {
        active_[i] = false;
        result_.cameras[i].reason = "no wand view agrees with the other cameras: check that camera " +
                                    std::to_string(intrinsics_.cameras[i].id) +
                                    "'s intrinsics belong to it, then wave the wand more in its view";
      }
    }
  }

  void Solve(int max_iterations) {
    WandBundleOptions pass_options = bundle_;
    pass_options.max_iterations = max_iterations;
    const WandBundleSummary summary = AdjustWandBundle(frames_, wand_, pass_options, active_, &cameras_, &poses_);
    result_.solver_iterations += summary.iterations;
    result_.solver_message = summary.message;
    if (!summary.usable) {
      throw std::runtime_error("bundle adjustment failed (" + summary.message +
                               "): record the wand again, covering the volume slowly");
    }
  }

  // Re-labels the frames and drops the views beyond the robust gate; returns how many were dropped.
  size_t Reject() {
    const double sigma = RobustSigmaPx(cameras_, wand_, frames_, poses_);
    const double gate = std::max(options_.outlier_min_px, options_.outlier_sigmas * sigma);
    const size_t dropped = RelabelAndReject(cameras_, wand_, gate, &frames_, &poses_);
    RefuseUnseen();
    return dropped;
  }

  void BundleAdjust() {
    // Early passes only need to get close enough to separate outliers: with wrong views still in,
    // the robust loss makes convergence slow, and they are about to be removed anyway.
    for (int pass = 0; pass + 1 < options_.refinement_passes; ++pass) {
      Solve(std::min(options_.early_pass_iterations, bundle_.max_iterations));
      Reject();
    }
    Solve(bundle_.max_iterations);
    if (Reject() > 0) Solve(bundle_.max_iterations);
  }

  // Report: residuals, coverage and independently triangulated wand lengths, then acceptance.
  // Returns the cameras refused by this evaluation.
  std::vector<size_t> Evaluate() {
    const int grid = options_.coverage_grid;
    std::vector<std::vector<bool>> cells(n_, std::vector<bool>(static_cast<size_t>(grid * grid), false));
    std::vector<ReprojectionSum> camera_sums(n_);
    std::vector<std::vector<double>> length_errors(n_);
    std::vector<double> all_length_errors;
    std::vector<size_t> views_used(n_, 0);
    ReprojectionSum total;
    WandCalibrationFigures& figures = result_.figures;
    figures = WandCalibrationFigures{};
    figures.coverage_grid = grid;
    figures.coverage.assign(n_, std::vector<uint32_t>(static_cast<size_t>(grid * grid), 0));
    figures.residuals_px.assign(n_, {});
    const size_t centre_step = frames_.size() / 2000 + 1;
    const size_t last = wand_.MarkerCount() - 1;
    for (size_t f = 0; f < frames_.size(); ++f) {
      if (f % centre_step == 0) figures.wand_centres.push_back(poses_[f].centre);
      std::vector<PointView> first, second;
      for (const WandView& view : frames_[f].views) {
        const Camera& camera = cameras_[view.camera];
        ++views_used[view.camera];
        for (size_t k = 0; k < view.pixels.size(); ++k) {
          camera_sums[view.camera].Add(camera, poses_[f].Marker(wand_, k), view.pixels[k]);
          total.Add(camera, poses_[f].Marker(wand_, k), view.pixels[k]);
          Eigen::Vector2d projected;
          if (camera.ProjectToPixel(poses_[f].Marker(wand_, k), &projected))
            figures.residuals_px[view.camera].push_back(static_cast<float>((projected - view.pixels[k]).norm()));
          const int cx = std::clamp(static_cast<int>(view.pixels[k].x() * grid / camera.intrinsics.width), 0, grid - 1);
          const int cy =
              std::clamp(static_cast<int>(view.pixels[k].y() * grid / camera.intrinsics.height), 0, grid - 1);
          cells[view.camera][static_cast<size_t>(cy * grid + cx)] = true;
          ++figures.coverage[view.camera][static_cast<size_t>(cy * grid + cx)];
        }
        // Normalized coordinates again: the intrinsics may have been refined.
        first.push_back({camera.ProjectionMatrix(), camera.UndistortPixel(view.pixels[0])});
        second.push_back({camera.ProjectionMatrix(), camera.UndistortPixel(view.pixels[last])});
      }
      Eigen::Vector3d a, b;
      if (!TriangulatePoint(first, &a) || !TriangulatePoint(second, &b)) continue;
      const double error = (b - a).norm() - wand_.LengthMm();
      all_length_errors.push_back(error);
      for (const WandView& view : frames_[f].views) length_errors[view.camera].push_back(error);
    }
    figures.wand_length_errors_mm = all_length_errors;
    result_.wand_length = SummarizeLengthErrors(all_length_errors);
    result_.reprojection_rms_px = total.RmsPx();
    result_.unprojected_observations = total.unprojected;

    for (size_t i = 0; i < n_; ++i) {
      if (!active_[i]) continue;  // a camera refused earlier keeps the figures it was refused on
      CameraCalibrationReport& report = result_.cameras[i];
      report.views_used = views_used[i];
      report.coverage = static_cast<double>(std::count(cells[i].begin(), cells[i].end(), true)) / (grid * grid);
      report.reprojection_rms_px = camera_sums[i].RmsPx();
      report.wand_length = SummarizeLengthErrors(length_errors[i]);
    }
    std::vector<double> active_rms;
    for (size_t i = 0; i < n_; ++i) {
      if (active_[i] && result_.cameras[i].views_used > 0) active_rms.push_back(result_.cameras[i].reprojection_rms_px);
    }
    double median_rms = 0.0;
    if (!active_rms.empty()) {
      std::nth_element(active_rms.begin(), active_rms.begin() + static_cast<long>(active_rms.size() / 2),
                       active_rms.end());
      median_rms = active_rms[active_rms.size() / 2];
    }
    result_.rig.cameras.clear();
    std::vector<size_t> refused;
    for (size_t i = 0; i < n_; ++i) {
      CameraCalibrationReport& report = result_.cameras[i];
      const std::string id = std::to_string(report.id);
      if (!active_[i]) continue;  // reason already set
      char buffer[320];
      const double inliers = report.views_selected > 0
                                 ? static_cast<double>(report.views_used) / static_cast<double>(report.views_selected)
                                 : 0.0;
      if (static_cast<int>(report.views_used) < options_.min_views_per_camera) {
        report.reason = "only " + std::to_string(report.views_used) + " wand views survived outlier rejection (need " +
                        std::to_string(options_.min_views_per_camera) + "): wave the wand more in camera " + id +
                        "'s view";
      } else if (report.coverage < options_.min_coverage) {
        std::snprintf(buffer, sizeof(buffer),
                      "the wand covered %.0f %% of the image (need %.0f %%): wave it towards the edges and corners "
                      "of camera %s's view",
                      100.0 * report.coverage, 100.0 * options_.min_coverage, id.c_str());
        report.reason = buffer;
      } else if (report.reprojection_rms_px > options_.max_camera_rms_px ||
                 report.reprojection_rms_px > options_.max_rms_ratio * median_rms) {
        std::snprintf(buffer, sizeof(buffer),
                      "reprojection RMS %.2f px (limit %.2f px, %.1f times the rig's median %.2f px): check camera "
                      "%s's intrinsics and that it did not move, then record the wand again",
                      report.reprojection_rms_px, options_.max_camera_rms_px, options_.max_rms_ratio, median_rms,
                      id.c_str());
        report.reason = buffer;
      } else if (inliers < options_.min_inlier_fraction) {
        std::snprintf(buffer, sizeof(buffer),
                      "only %.0f %% of its wand views agree with the other cameras (need %.0f %%): check camera %s's "
                      "intrinsics and that it did not move, then record the wand again",
                      100.0 * inliers, 100.0 * options_.min_inlier_fraction, id.c_str());
        report.reason = buffer;
      } else {
        report.accepted = true;
        result_.rig.cameras.push_back(cameras_[i]);
        // The centroid noise the reconstruction's gates follow (DESIGN.md, recon/rig_noise.h).
        result_.rig.cameras.back().centroid_rms_px = report.reprojection_rms_px;
      }
      if (!report.accepted) refused.push_back(i);
    }
    return refused;
  }

  // A refused camera must not bend the others: solve once more without it.
  void SolveWithout(const std::vector<size_t>& refused) {
    for (size_t i : refused) active_[i] = false;
    std::vector<WandFrame> kept_frames;
    std::vector<WandPose> kept_poses;
    for (size_t f = 0; f < frames_.size(); ++f) {
      auto& views = frames_[f].views;
      views.erase(std::remove_if(views.begin(), views.end(), [&](const WandView& v) { return !active_[v.camera]; }),
                  views.end());
      if (views.size() < 2) continue;
      kept_frames.push_back(std::move(frames_[f]));
      kept_poses.push_back(poses_[f]);
    }
    frames_ = std::move(kept_frames);
    poses_ = std::move(kept_poses);
    if (active_[init_.reference_camera]) {
      Solve(bundle_.max_iterations);
      Reject();
      result_.frames_used = frames_.size();
      Evaluate();
    }
  }

  const Rig& intrinsics_;
  const WandGeometry& wand_;
  const WandCalibrationOptions& options_;
  const size_t n_;
  WandCalibrationResult result_;
  std::vector<bool> active_;
  std::vector<WandFrame> frames_;
  std::vector<WandPose> poses_;  // one per frame
  WandInitialization init_;
  std::vector<Camera> cameras_;
  WandBundleOptions bundle_;
};

}  // namespace

void WandCalibrationOptions::Check() const {
  selection.Check();
  initialization.Check();
  bundle.Check();
  if (!(outlier_min_px > 0.0)) throw std::invalid_argument("outlier_min_px must be > 0");
  if (!(outlier_sigmas > 0.0)) throw std::invalid_argument("outlier_sigmas must be > 0");
  if (!(initial_gate_px > 0.0)) throw std::invalid_argument("initial_gate_px must be > 0");
  if (refinement_passes < 1) throw std::invalid_argument("refinement_passes must be >= 1");
  if (early_pass_iterations < 1) throw std::invalid_argument("early_pass_iterations must be >= 1");
  if (min_views_per_camera < 1) throw std::invalid_argument("min_views_per_camera must be >= 1");
  if (!(min_coverage >= 0.0 && min_coverage <= 1.0)) throw std::invalid_argument("min_coverage must be in [0, 1]");
  if (coverage_grid < 1) throw std::invalid_argument("coverage_grid must be >= 1");
  if (!(max_camera_rms_px > 0.0)) throw std::invalid_argument("max_camera_rms_px must be > 0");
  if (!(max_rms_ratio > 1.0)) throw std::invalid_argument("max_rms_ratio must be > 1");
  if (!(min_inlier_fraction >= 0.0 && min_inlier_fraction <= 1.0)) {
    throw std::invalid_argument("min_inlier_fraction must be in [0, 1]");
  }
}

bool WandCalibrationResult::AllAccepted() const {
  return std::all_of(cameras.begin(), cameras.end(), [](const CameraCalibrationReport& c) { return c.accepted; });
}

LengthErrorStats SummarizeLengthErrors(std::vector<double> errors_mm) {
  LengthErrorStats stats;
  stats.count = errors_mm.size();
  if (errors_mm.empty()) return stats;
  double sum = 0.0, sum_sq = 0.0;
  std::vector<double> magnitudes;
  for (double e : errors_mm) {
    sum += e;
    sum_sq += e * e;
    magnitudes.push_back(std::abs(e));
  }
  std::sort(magnitudes.begin(), magnitudes.end());
  const double n = static_cast<double>(errors_mm.size());
  stats.mean_mm = sum / n;
  stats.rms_mm = std::sqrt(sum_sq / n);
  stats.median_abs_mm = magnitudes[magnitudes.size() / 2];
  stats.p95_abs_mm = magnitudes[std::min(magnitudes.size() - 1, static_cast<size_t>(0.95 * n))];
  stats.max_abs_mm = magnitudes.back();
  return stats;
}

WandCalibrationResult CalibrateWand(const std::vector<FrameSet>& frame_sets, const Rig& intrinsics,
                                    const WandGeometry& wand, const WandCalibrationOptions& options) {
  wand.Check();
  options.Check();
  return WandSolver(intrinsics, wand, options).Run(frame_sets);
}

}  // namespace mocap
