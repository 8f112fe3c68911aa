// `reconstruct`: a session directory's 2D blobs -> labelled 3D trajectories in a TRC file, with
// the session's own calibration unless one is given, after a sample of frame sets has shown that
// the calibration fits the session (calib/calibration_fit.h).
// Streams: frame sets are reconstructed and tracked as they are read, rows leave the gap
// filler's bounded window for a spill file, and the TRC is written from it at the end, so memory
// does not grow with session length.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>

#include "cli/commands.h"
#include "cli/labels_helpers.h"
#include "cli/reconstruct_session.h"
#include "cli/progress.h"
#include "ingest/session.h"
#include "io/calibration_json.h"
#include "pipeline/offline_reconstruction.h"
#include "pipeline/take_outputs.h"
#include "recon/blob_time_align.h"
#include "recon/known_correspondences.h"
#include "bodies/body_live_filter.h"
#include "bodies/body_trajectories.h"
#include "io/trajectory_file.h"
#include "track/trc_spill.h"
#include "util/log.h"
#include "util/plain_name.h"

namespace mocap {
namespace {


// The whole-take steps over the finished marker file (pipeline/take_outputs.h), written back in
// place: names from a marker set; rigid bodies' poses beside it (OUT.bodies.tsv) and one virtual
// marker per body (its pivot). `live_bodies`: the bodies come from the live path instead.
void FinishTake(const ReconstructArgs& args, bool live_bodies) {
  const bool fit_bodies = !args.bodies.empty() && !live_bodies;
  if (args.labels.empty() && !fit_bodies) return;
  MarkerTrajectories markers = ReadTrajectories(args.output);
  if (!args.labels.empty()) {
    const std::string report = NameTakeFromFile(args.labels, -1, &markers, args.labeller);
    std::printf("%s: %s\n", args.output.c_str(), report.c_str());
  }
  if (fit_bodies) {
    const std::vector<RigidBodyDefinition> bodies = ReadBodiesFile(args.bodies);
    const pipeline::TakeBodies take = pipeline::FitTakeBodies(bodies, args.body_smoothing, &markers);
    const std::string poses = args.output.substr(0, args.output.find_last_of('.')) + ".bodies.tsv";
    WriteBodyPoses(poses, bodies, take.rows, markers.rate_hz);
    for (size_t b = 0; b < bodies.size(); ++b) {
      const BodySmoothingStats& s = take.smoothing[b];
      std::printf("%s: body %s fitted in %zu of %zu frames; orientation over +-%d frames in %zu, fewer in %zu, "
                  "alone in %zu (point noise %.3f mm per axis)\n",
                  poses.c_str(), bodies[b].name.c_str(), take.FramesFitted(b), take.rows.size(),
                  args.body_smoothing.half_window, s.refined, s.shrunk, s.unchanged, s.noise_mm);
      const std::string missed = take.MissSummary(b);
      if (!missed.empty()) std::printf("%s: body %s not fitted in %s\n", poses.c_str(), bodies[b].name.c_str(), missed.c_str());
    }
  }
  WriteTrajectories(markers, args.output);
}

// The live body path over the session (--bodies-live): what `serve --bodies` publishes, fed the
// same points (each frame's reconstruction, before tracking decides anything), frame by frame.
class LiveBodiesRun {
 public:
  LiveBodiesRun(const ReconstructArgs& args)
      : bodies_(ReadBodiesFile(args.bodies)), live_(bodies_, {}, args.body_filter) {}
  void Add(uint64_t frame_number, const std::vector<ReconstructedPoint>& points) {
    positions_.resize(points.size());
    for (size_t i = 0; i < points.size(); ++i) positions_[i] = points[i].point_in_world;
    rows_.push_back({frame_number, live_.Update(frame_number, positions_)});
  }
  void Finish(const ReconstructArgs& args, double rate_hz) const {
    const std::string poses = args.output.substr(0, args.output.find_last_of('.')) + ".bodies.tsv";
    WriteBodyPoses(poses, bodies_, rows_, rate_hz);
    for (size_t b = 0; b < bodies_.size(); ++b) {
      size_t tracked = 0;
      for (const BodyPoseRow& row : rows_) tracked += row.poses[b].tracked;
      const BodyLiveFilterStats s = live_.filter().stats(b);
      std::printf("%s: body %s fitted in %zu of %zu frames (live); orientation over this and %d past frames in %zu, "
                  "fewer in %zu, alone in %zu (point noise %.3f mm per axis)\n",
                  poses.c_str(), bodies_[b].name.c_str(), tracked, rows_.size(), args.body_filter.past_frames,
                  s.refined, s.shrunk, s.unchanged, s.noise_mm);
    }
  }

 private:
  std::vector<RigidBodyDefinition> bodies_;
  LiveBodyTracker live_;
  std::vector<Eigen::Vector3d> positions_;
  std::vector<BodyPoseRow> rows_;
};

// Every camera of the session must be in the calibration: reconstructing with a camera's blobs
// silently ignored would give plausible-looking but thinner results.
void CheckCalibrationMatches(const SessionInfo& info, const Rig& rig, const ReconstructArgs& args) {
  for (uint32_t id : info.camera_ids) {
    if (rig.Find(id) == nullptr) {
      throw std::runtime_error(args.calibration + ": has no camera " + std::to_string(id) +
                               " but session " + args.session + " recorded it");
    }
  }
  if (rig.cameras.size() < 2) throw std::runtime_error(args.calibration + ": needs at least 2 cameras");
}

// A sample of the session's frame sets (spread evenly, free-running cameras' blobs brought to
// their instant as the reconstruction will) judges the calibration before hours of reconstruction
// go into a wrong one.
void CheckCalibrationFits(const ReconstructArgs& args, const Rig& rig) {
  SessionReader reader;
  reader.Open(args.session);
  reader.CheckImageSizes(ImageSizesOf(rig));
  const SessionInfo& info = reader.Info();
  const uint64_t stride = std::max<uint64_t>(1, info.frame_sets / args.fit.frame_sets);
  std::unique_ptr<BlobTimeAligner> aligner;
  if (info.free_run && !args.no_time_align) {
    BlobTimeAlignOptions align;
    align.rate_hz = info.rate_hz;
    align.epoch_ns = info.epoch_ns;
    aligner = std::make_unique<BlobTimeAligner>(align);
  }
  CalibrationFitCheck check(rig, args.fit, args.chain.recon);
  FrameSet frame_set;
  size_t judged = 0;
  for (uint64_t n = 0; judged < args.fit.frame_sets && reader.Next(&frame_set); ++n) {
    if (aligner) aligner->Align(&frame_set);
    if (n % stride != 0) continue;
    check.Add(frame_set);
    ++judged;
  }
  const CalibrationFit fit = check.Judge();
  if (fit.Fits()) {
    std::printf("%s: fits %s: median leave-one-out residual per camera %s, over %zu points of %zu frame sets\n",
                args.calibration.c_str(), args.session.c_str(), fit.PerCamera().c_str(), fit.points, fit.frame_sets);
    return;
  }
  const std::string reason = args.calibration + " does not fit " + args.session + ": " + fit.Misfits() +
                             " (moved or turned since that calibration?); median leave-one-out residual per camera " +
                             fit.PerCamera() + ", over " + std::to_string(fit.points) + " points of " +
                             std::to_string(fit.frame_sets) + " frame sets";
  if (!args.force_calibration)
    throw std::runtime_error(reason + "; calibrate again or --force-calibration to reconstruct anyway");
  log::Warn("{} (--force-calibration: reconstructing anyway)", reason);
}

// The known-correspondence floor of a simulated session: every true marker triangulated from its
// own unmerged blobs, no matching or tracking, columns named as in the truth. `eval` of this file
// against the truth is the accuracy a reconstruction could reach on these blobs.
void WriteKnownCorrespondenceFloor(const ReconstructArgs& args, const Rig& rig, SessionReader* reader) {
  const MarkerTrajectories truth = ReadTrajectories(args.known_correspondences);
  std::map<uint64_t, size_t> truth_row;
  for (size_t f = 0; f < truth.NumFrames(); ++f) truth_row[truth.frame_numbers[f]] = f;
  MarkerTrajectories floor;
  floor.rate_hz = reader->Info().rate_hz;
  floor.names = truth.names;
  const RigModel rig_model(rig);
  FrameSet frame_set;
  FrameViews views;
  std::vector<Eigen::Vector3d> true_points(truth.NumMarkers()), positions;
  std::vector<std::vector<int>> true_views;
  size_t frames = 0, points = 0;
  while (reader->Next(&frame_set)) {
    const auto row = truth_row.find(frame_set.frame_number);
    if (row == truth_row.end()) continue;
    if (!floor.frame_numbers.empty() && frame_set.frame_number <= floor.frame_numbers.back()) continue;
    for (size_t m = 0; m < truth.NumMarkers(); ++m) true_points[m] = truth.At(row->second, m);
    BuildFrameViews(rig_model, frame_set, &views);
    FindTrueViews(rig_model, views, true_points, KnownCorrespondenceOptions(), &true_views);
    points += TriangulateKnownCorrespondences(rig_model, views, true_views, args.chain.recon.triangulation, &positions);
    const size_t f = floor.AddFrame(frame_set.frame_number);
    for (size_t m = 0; m < positions.size(); ++m) floor.At(f, m) = positions[m];
    ++frames;
  }
  if (frames == 0) {
    throw std::runtime_error(args.session + ": no frame set matches a frame of " + args.known_correspondences);
  }
  WriteTrajectories(floor, args.output);
  std::printf("%s: known-correspondence floor, %zu frames, %.2f points/frame\n", args.output.c_str(), frames,
              static_cast<double>(points) / static_cast<double>(frames));
}

}  // namespace

std::string SessionCalibration(const std::string& session) {
  const SessionInfo info = LoadSessionInfo(session);
  if (!PlainName(info.calibration, 255))
    throw std::runtime_error(session + ": session.json names its calibration '" + info.calibration +
                             "', not a file of the session; give a calibration (--calibration, a recipe's \"calibration\")");
  const std::filesystem::path own = std::filesystem::path(session) / info.calibration;
  if (!std::filesystem::is_regular_file(own))
    throw std::runtime_error(session + ": has no calibration of its own (" + info.calibration +
                             "); give a calibration (--calibration, a recipe's \"calibration\")");
  return own.string();
}

void ReconstructSession(ReconstructArgs args) {
  try {
    OutputTrajectoryFormatOf(args.output);
  } catch (const std::invalid_argument& error) {
    throw UsageError(error.what());
  }
  args.chain.recon.matcher = MatcherTypeFromString(args.matcher);
  args.chain.recon.use_predictions = !args.no_predictions;
  args.chain.tracker.assignment = AssignmentMethodFromString(args.assignment);
  CheckOptions(args.chain.recon);  // out-of-range numbers are usage errors, before any file is read
  CheckOptions(args.chain.tracker);
  args.fit.Check();
  if (args.calibration.empty()) {
    args.calibration = SessionCalibration(args.session);
    std::printf("%s: calibration %s (the session's own)\n", args.session.c_str(), args.calibration.c_str());
  }
  const Rig rig = LoadRigJson(args.calibration);
  SessionReader reader;
  reader.Open(args.session);
  const SessionInfo& info = reader.Info();
  if (!(info.rate_hz > 0.0)) throw std::runtime_error(args.session + ": session.json has no frame rate");
  CheckCalibrationMatches(info, rig, args);
  reader.CheckImageSizes(ImageSizesOf(rig));
  CheckCalibrationFits(args, rig);
  if (!args.known_correspondences.empty()) {
    WriteKnownCorrespondenceFloor(args, rig, &reader);
    return;
  }
  TrcSpill spill;
  spill.Open(args.output, info.rate_hz);
  pipeline::OfflineReconstruction chain(rig, info.rate_hz, args.chain,
                                        [&spill](uint64_t frame, const std::vector<TrackSample>& row) {
                                          spill.AddRow(frame, row);
                                        });

  std::unique_ptr<LiveBodiesRun> live_bodies;
  if (args.bodies_live) {
    if (args.bodies.empty()) throw UsageError("--bodies-live needs --bodies");
    live_bodies = std::make_unique<LiveBodiesRun>(args);
  }
  // Sessions processed side by side (`process --jobs`) draw no bar: one line cannot show several.
  std::unique_ptr<ProgressBar> progress;
  if (args.progress || !args.progress_file.empty())
    progress = std::make_unique<ProgressBar>("reconstruct", static_cast<size_t>(info.frame_sets), args.progress_file);
  // Free-running cameras' blobs are brought to each frame set's instant (recon/blob_time_align.h).
  std::unique_ptr<BlobTimeAligner> aligner;
  if (info.free_run && !args.no_time_align) {
    BlobTimeAlignOptions align;
    align.rate_hz = info.rate_hz;
    align.epoch_ns = info.epoch_ns;
    aligner = std::make_unique<BlobTimeAligner>(align);
  }
  FrameSet frame_set;
  while (reader.Next(&frame_set)) {
    if (aligner) aligner->Align(&frame_set);
    if (!chain.Add(frame_set)) continue;  // the reader guarantees order
    if (live_bodies) live_bodies->Add(frame_set.frame_number, chain.points());
    if (progress) progress->Update(chain.frames());
  }
  if (progress) progress->Finish();
  const size_t done = chain.frames();
  if (done == 0) throw std::runtime_error(args.session + ": no frames to reconstruct");
  const int columns = chain.Finish();
  spill.Finish(columns);
  FinishTake(args, live_bodies != nullptr);
  if (live_bodies) live_bodies->Finish(args, info.rate_hz);

  for (const std::string& warning : reader.warnings()) log::Warn("{}", warning);
  const ReconstructionStats& rs = chain.reconstructor().stats();
  const TrackerStats& ts = chain.tracker().stats();
  std::printf(
      "%s: %zu frames, %d markers, %.2f points/frame (%.1f%% via predictions), %lld outlier views "
      "rejected, %lld duplicate or ghost points dropped, %lld re-acquisitions, %lld swaps undone in hindsight, %lld tracks joined to the marker they "
      "continue, %lld rigid-model and %lld spline samples (matcher %s)\n",
      args.output.c_str(), done, columns,
      static_cast<double>(rs.points) / static_cast<double>(done),
      rs.points > 0 ? 100.0 * static_cast<double>(rs.points_from_predictions) / rs.points : 0.0,
      rs.outlier_views_rejected, rs.ghosts_rejected, ts.reacquisitions, chain.hindsight().swaps_undone(),
      chain.hindsight().columns_joined(), ts.predicted_samples, chain.gap_filler().filled_samples(),
      args.matcher.c_str());
  if (aligner) {
    std::printf("%s: free-running cameras: %llu blobs brought to their frame set's instant, %llu left as captured "
                "(no partner in the camera's previous frame)\n",
                args.session.c_str(), static_cast<unsigned long long>(aligner->stats().blobs_moved),
                static_cast<unsigned long long>(aligner->stats().blobs_kept));
  }
  const SessionReadStats& read = reader.stats();
  if (read.rescaled_frames > 0 || read.wrong_size_frames > 0) {
    std::printf("%s: camera frames of another image size than the calibration's: %llu rescaled, %llu refused\n",
                args.session.c_str(), static_cast<unsigned long long>(read.rescaled_frames),
                static_cast<unsigned long long>(read.wrong_size_frames));
  }
  if (read.damaged_log_stretches > 0) {
    std::printf("%s: raw log damaged: %llu stretch%s skipped (%llu bytes), every good record around them read\n",
                args.session.c_str(), static_cast<unsigned long long>(read.damaged_log_stretches),
                read.damaged_log_stretches == 1 ? "" : "es", static_cast<unsigned long long>(read.skipped_log_bytes));
  }
}

void AddReconstructCommand(CLI::App& app) {
  CLI::App* command = app.add_subcommand("reconstruct", "2D blobs of a session -> labelled 3D markers (TRC)");
  auto args = std::make_shared<ReconstructArgs>();
  command->add_option("session", args->session, "Session directory")->required()->check(CLI::ExistingDirectory);
  command->add_option("--calibration", args->calibration,
                      "Calibration JSON (default: the session's own, the file its session.json names); checked "
                      "against a sample of the session's frame sets first")
      ->check(CLI::ExistingFile);
  command->add_flag("--force-calibration", args->force_calibration,
                    "Reconstruct even when a camera's residuals show the calibration does not fit the session "
                    "(printed as a warning)");
  command->add_option("--fit-frame-sets", args->fit.frame_sets,
                      "Frame sets (spread over the session) that judge the calibration first")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  command->add_option("-o,--output", args->output, "Output marker file: .trc or .c3d")->required();
  command->add_option("--bodies", args->bodies,
                      "Rigid bodies file: their poses to OUT.bodies.tsv and a virtual marker each (memory then "
                      "grows with the session)")
      ->check(CLI::ExistingFile);
  command->add_option("--bodies-window", args->body_smoothing.half_window,
                      "Rigid bodies: each orientation refitted over this many frames each side, fewer where the "
                      "motion disagrees with the model (0: each frame alone)")
      ->check(CLI::Range(0, 50))
      ->capture_default_str();
  command->add_option("--bodies-degree", args->body_smoothing.degree,
                      "Rigid bodies: degree of the orientation's polynomial over that window (1: steady angular "
                      "velocity, 2: steady angular acceleration)")
      ->check(CLI::Range(1, 3))
      ->capture_default_str();
  command->add_flag("--bodies-live", args->bodies_live,
                    "Rigid bodies: the live path instead (as `serve --bodies` publishes them: each frame's points "
                    "before tracking, each orientation from that frame and past ones only); no virtual markers");
  command->add_option("--bodies-live-window", args->body_filter.past_frames,
                      "Rigid bodies, live path: each orientation refitted over this frame and up to this many "
                      "before it, fewer where the motion disagrees (0: each frame alone)")
      ->check(CLI::Range(0, 100))
      ->capture_default_str();
  command->add_option("--bodies-live-degree", args->body_filter.degree,
                      "Rigid bodies, live path: degree of the orientation's polynomial over that window")
      ->check(CLI::Range(1, 3))
      ->capture_default_str();
  command->add_option("--labels", args->labels,
                      "Marker set (labels learn): named columns for the markers it places, M001... for the rest")
      ->check(CLI::ExistingFile);
  AddLabellerOptions(*command, &args->labeller, "--labels-explain");
  command->add_option("--known-correspondences", args->known_correspondences,
                      "Simulated session's truth TRC: triangulate each true marker from its own unmerged blobs "
                      "instead (the known-correspondence floor for eval)")
      ->check(CLI::ExistingFile);
  command->add_option("--matcher", args->matcher, "Correspondences of untracked blobs")
      ->check(CLI::IsMember({"relaxation", "clustering", "greedy"}))
      ->capture_default_str();
  command->add_option("--assignment", args->assignment, "Predictions to points")
      ->check(CLI::IsMember({"optimal", "greedy"}))
      ->capture_default_str();
  command->add_flag("--no-time-align", args->no_time_align,
                    "Free-run sessions: triangulate each camera's blobs as captured, not brought to the frame "
                    "set's instant along their 2D tracks");
  command->add_flag("--no-predictions", args->no_predictions,
                    "Match every frame from scratch (no reprojected track predictions)");
  command->add_option("--contested-gate-factor", args->chain.recon.prediction.contested_gate_factor,
                      "Predictions nearer each other than this times the sum of their gates (each counted up to "
                      "30 mm) are left to the matcher (dense clusters); 0 serves every prediction")
      ->capture_default_str();
  command->add_flag(
      "--contested-groups", [args](int64_t) { args->chain.recon.prediction.resolve_contested_groups = true; },
      "Assign each group of contested predictions to blobs per camera instead of leaving their blobs to the matcher "
      "(recon/contested_groups.h: faster on dense sets)");
  command->add_option("--threads", args->chain.recon.threads,
                      "Worker threads inside a frame (undistortion, blob index, predictions); results are identical "
                      "for any count")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  command->add_option("--max-ray-distance-mm", args->chain.recon.graph.max_ray_distance_mm,
                      "Epipolar graph: rays closer than this are linked (at least: the gate widens with the "
                      "centroid noise)")->capture_default_str();
  command->add_option("--cluster-distance-mm", args->chain.recon.clustering.max_ray_distance_mm,
                      "Clustering matcher threshold (at least; widens with the noise)")->capture_default_str();
  command->add_option("--max-reprojection-px", args->chain.recon.triangulation.max_reprojection_px,
                      "Views with a larger residual are rejected (at least; widens to 4 sigmas of the noise)")
      ->capture_default_str();
  AddRigOptions(*command, &args->chain.recon, &args->chain.tracker);
  command->add_flag("--no-hindsight-swaps", [args](int64_t) { args->chain.hindsight.enabled = false; },
                    "Keep identity trades between close markers as tracked (by default a trade that both "
                    "trajectories' next frames show is undone)");
  command->add_option("--max-spline-gap-s", args->chain.max_spline_gap_s,
                      "Longest gap (seconds) filled by a spline")->capture_default_str();
  command->callback([args]() { ReconstructSession(*args); });
}

}  // namespace mocap
