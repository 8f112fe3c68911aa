// Frame loop of `sim project`: project, write datagrams, keep the truth and visibility beside.
#include "sim/project_session.h"

#include <cmath>
#include <deque>
#include <filesystem>
#include <random>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "ingest/session.h"
#include "io/calibration_json.h"
#include "io/trc.h"
#include "io/visibility.h"

namespace mocap {

ProjectSessionStats ProjectSession(const MarkerTrajectories& motion, const Rig& rig, const ProjectOptions& options,
                                   const std::string& dir, const std::function<void(size_t, size_t)>& progress,
                                   const std::vector<CameraBump>& bumps) {
  options.Check();
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
    const std::vector<CameraFrame> frames = projector.Project(frame_number, trigger_ns, points, &cameras_seeing);
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
