// Frame loop of `sim project`: project, write datagrams, keep the truth and visibility beside.
#include "sim/project_session.h"

#include <cmath>
#include <algorithm>
#include <deque>
#include <map>
#include <filesystem>
#include <random>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "ingest/session.h"
#include "io/calibration_json.h"
#include "io/trc.h"
#include "io/visibility.h"

namespace mocap {

void FreeRunOptions::Check() const {
  if (!(rate_error_ppm >= 0.0 && rate_error_ppm <= 1e5))
    throw std::invalid_argument("--rate-error-ppm must be 0..100000, not " + std::to_string(rate_error_ppm));
  if (!(jitter_ms >= 0.0 && jitter_ms <= 1000.0))
    throw std::invalid_argument("--time-jitter-ms must be 0..1000, not " + std::to_string(jitter_ms));
}

namespace {

// Where each free-running camera exposes, in frame periods from its slot's instant.
class FreeRunClocks {
 public:
  FreeRunClocks(const FreeRunOptions& options, size_t cameras) : options_(options), rng_(options.seed ^ 0x66726565ull) {
    std::uniform_real_distribution<double> unit(-0.5, 0.5);
    for (size_t c = 0; c < cameras; ++c) {
      phase_.push_back(unit(rng_));
      rate_error_.push_back(2.0 * unit(rng_) * options.rate_error_ppm * 1e-6);
    }
  }
  // Camera c's exposure at nominal frame index f, periods from the slot's instant, in [-0.5, 0.5).
  double Offset(size_t c, size_t f) const {
    const double drift = phase_[c] - rate_error_[c] * static_cast<double>(f);
    return drift - std::floor(drift + 0.5);
  }
  // The stamp's error, ns.
  int64_t Jitter() { return std::llround(jitter_(rng_) * options_.jitter_ms * 1e6); }
  nlohmann::json ToJson() const {
    nlohmann::json cameras = nlohmann::json::array();
    for (size_t c = 0; c < phase_.size(); ++c) cameras.push_back({{"phase", phase_[c]}, {"rate_error", rate_error_[c]}});
    return {{"rate_error_ppm", options_.rate_error_ppm}, {"jitter_ms", options_.jitter_ms}, {"seed", options_.seed},
            {"cameras", cameras}};
  }

 private:
  FreeRunOptions options_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> jitter_{0.0, 1.0};
  std::vector<double> phase_, rate_error_;
};

// The motion's positions `offset` frames after frame f (linear between frames, held at the ends;
// NaN where a neighbour lacks the marker).
void PointsAt(const MarkerTrajectories& motion, size_t f, double offset, std::vector<Eigen::Vector3d>* out) {
  const size_t markers = motion.NumMarkers();
  const double at = std::clamp(static_cast<double>(f) + offset, 0.0, static_cast<double>(motion.NumFrames() - 1));
  const size_t first = static_cast<size_t>(std::floor(at));
  const double t = at - static_cast<double>(first);
  const size_t second = std::min(first + 1, motion.NumFrames() - 1);
  out->resize(markers);
  for (size_t m = 0; m < markers; ++m) {
    const Eigen::Vector3d& a = motion.points[first * markers + m];
    (*out)[m] = t > 0.0 ? Eigen::Vector3d((1.0 - t) * a + t * motion.points[second * markers + m]) : a;
  }
}

}  // namespace

ProjectSessionStats ProjectSession(const MarkerTrajectories& motion, const Rig& rig, const ProjectOptions& options,
                                   const std::string& dir, const std::function<void(size_t, size_t)>& progress,
                                   const std::vector<CameraBump>& bumps, const FreeRunOptions& free_run) {
  options.Check();
  free_run.Check();
  if (!(motion.rate_hz > 0.0)) throw std::invalid_argument("motion rate must be positive");
  if (rig.cameras.empty()) throw std::invalid_argument("rig has no cameras");
  // The rig the cameras really have: the projector reads it every frame, bumps change it.
  Rig seen = rig;
  Rig after_bumps = rig;
  nlohmann::json bump_list = nlohmann::json::array();
  for (const CameraBump& bump : bumps) {
    if (!(bump.from_s >= 0.0) || !std::isfinite(bump.from_s))
      throw std::invalid_argument("a camera bump's time must be >= 0 s");
    ApplyCameraBump(bump, &after_bumps);
    bump_list.push_back(
        {{"camera", bump.camera_id}, {"degrees", bump.degrees}, {"mm", bump.mm}, {"from_s", bump.from_s}, {"seed", bump.seed}});
  }
  std::vector<char> bumped(bumps.size(), 0);

  SessionInfo info;
  info.rate_hz = motion.rate_hz;
  info.epoch_ns = kSimEpochNs;
  for (const Camera& camera : rig.cameras) info.camera_ids.push_back(camera.id);
  info.source = "sim project";
  info.extra["sim"] = {{"noise_px", options.noise_px},
                       {"occlusion", options.occlusion},
                       {"occlusion_frames", options.occlusion_frames},
                       {"spurious", options.spurious},
                       {"merge_px", options.merge_px},
                       {"drop_frames", options.drop_frames},
                       {"late", options.late},
                       {"late_frames", options.late_frames},
                       {"marker_diameter_mm", options.marker_diameter_mm},
                       {"seed", options.seed},
                       {"truth", "truth.trc"},
                       {"visibility", "visibility.tsv"}};
  FreeRunClocks clocks(free_run, rig.cameras.size());
  if (free_run.enabled) {
    info.free_run = true;
    info.extra["sim"]["free_run"] = clocks.ToJson();
  }
  if (!bumps.empty()) {
    info.extra["sim"]["bumps"] = bump_list;
    info.extra["sim"]["truth_calibration"] = "truth.calibration.json";
  }

  SessionWriter writer;
  writer.Create(dir, info, SessionWriter::Existing::kReplace);
  const std::filesystem::path root(dir);
  SaveRigJson(rig, (root / info.calibration).string());
  if (!bumps.empty()) SaveRigJson(after_bumps, (root / "truth.calibration.json").string());
  WriteTrc(motion, (root / "truth.trc").string());
  VisibilityWriter visibility;
  visibility.Open((root / "visibility.tsv").string(), motion.names);

  FaultyProjector projector(seen, motion.NumMarkers(), options);
  ProjectSessionStats stats;
  // Late camera frames wait here until `late_frames` later frames have been written.
  struct Delayed {
    size_t release_after;  // frame index after which it is written
    CameraFrame frame;
  };
  std::deque<Delayed> delayed;
  std::mt19937_64 late_rng(options.seed ^ 0x6c617465ull);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double period_ns = 1e9 / motion.rate_hz;
  // A datagram crosses a quiet LAN in about 0.2 ms.
  constexpr uint64_t kNetworkNs = 200000;
  std::vector<int> cameras_seeing;
  const size_t markers = motion.NumMarkers();
  std::vector<std::vector<Eigen::Vector3d>> exposed(rig.cameras.size());
  std::map<uint32_t, size_t> camera_index;
  for (size_t c = 0; c < rig.cameras.size(); ++c) camera_index[rig.cameras[c].id] = c;
  for (size_t f = 0; f < motion.NumFrames(); ++f) {
    const uint64_t frame_number = motion.frame_numbers[f];
    const double seconds = (static_cast<double>(frame_number) - static_cast<double>(motion.frame_numbers[0])) / motion.rate_hz;
    for (size_t b = 0; b < bumps.size(); ++b) {
      if (bumped[b] || seconds < bumps[b].from_s) continue;
      ApplyCameraBump(bumps[b], &seen);
      bumped[b] = 1;
    }
    const uint64_t trigger_ns =
        kSimEpochNs + static_cast<uint64_t>(std::llround(static_cast<double>(frame_number) * 1e9 / motion.rate_hz));
    const Eigen::Vector3d* points = markers > 0 ? &motion.points[f * markers] : nullptr;
    std::vector<CameraFrame> frames;
    if (free_run.enabled) {
      std::vector<const Eigen::Vector3d*> camera_points(rig.cameras.size());
      for (size_t c = 0; c < rig.cameras.size(); ++c) {
        PointsAt(motion, f, clocks.Offset(c, f), &exposed[c]);
        camera_points[c] = exposed[c].data();
      }
      frames = projector.Project(frame_number, trigger_ns, camera_points, &cameras_seeing);
      for (CameraFrame& frame : frames) {
        const size_t c = camera_index.at(frame.camera_id);
        frame.trigger_time_ns = 0;
        frame.flags |= kFrameFreeRun;
        frame.capture_time_ns = static_cast<uint64_t>(static_cast<int64_t>(trigger_ns) +
                                                      std::llround(clocks.Offset(c, f) * period_ns) + clocks.Jitter());
        frame.send_time_ns = frame.capture_time_ns + 1500000;
      }
    } else {
      frames = projector.Project(frame_number, trigger_ns, points, &cameras_seeing);
    }
    for (const CameraFrame& frame : frames) {
      stats.blobs += frame.blobs.size();
      for (const Blob& blob : frame.blobs) stats.merged_blobs += (blob.flags & kBlobMerged) ? 1 : 0;
      if (options.late > 0.0 && unit(late_rng) < options.late) {
        CameraFrame late = frame;
        late.receive_time_ns = frame.send_time_ns + kNetworkNs +
                               static_cast<uint64_t>(std::llround(options.late_frames * period_ns));
        delayed.push_back({f + static_cast<size_t>(options.late_frames), std::move(late)});
        ++stats.late_camera_frames;
        continue;
      }
      CameraFrame on_time = frame;
      on_time.receive_time_ns = frame.send_time_ns + kNetworkNs;
      writer.Write(on_time);
    }
    while (!delayed.empty() && delayed.front().release_after <= f) {
      writer.Write(delayed.front().frame);
      delayed.pop_front();
    }
    ++stats.frames;
    stats.camera_frames += frames.size();
    stats.dropped_camera_frames += rig.cameras.size() - frames.size();
    for (size_t m = 0; m < markers; ++m) {
      if (!motion.Has(f, m)) continue;
      ++stats.present;
      stats.reconstructible += cameras_seeing[m] >= 2 ? 1 : 0;
    }
    visibility.WriteFrame(frame_number, cameras_seeing);
    if (progress) progress(f + 1, motion.NumFrames());
  }
  for (const Delayed& late : delayed) writer.Write(late.frame);
  visibility.Close();
  // The writer counts a new frame set whenever the frame number changes, which late frames do.
  writer.info().frame_sets = stats.frames;
  writer.info().dropped_camera_frames = stats.dropped_camera_frames;
  writer.info().extra["sim"]["late_camera_frames"] = stats.late_camera_frames;
  writer.info().extra["sim"]["blobs"] = stats.blobs;
  writer.info().extra["sim"]["merged_blobs"] = stats.merged_blobs;
  writer.Finish();
  return stats;
}

}  // namespace mocap
