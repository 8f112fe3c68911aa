// `bench`: per-frame reconstruct + track time on a simulated session built in memory (default
// 16 cameras, 60 markers, 240 Hz, the faults), side by side in the same run with the
// floor: undistorting and triangulating the same frames given the true correspondences. Prints
// the real-time factor (frame period / mean time per frame), p99 against the median, the cold
// start and where the time goes. `--motion FILE` replays a recorded motion instead, `--threads N`
// runs each frame on N threads (wall clock then), `--table` runs cameras x markers cases.
// `bench --ingest`: the hub's datagram ingest (envelope opened and checked, packet decoded,
// chunks and frame sets assembled) on the same simulated session's datagrams, authenticated and
// on the insecure development wire, in datagrams per second of one thread.
#include <algorithm>
#include <filesystem>
#include <map>
#include <unistd.h>
#include <chrono>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "ingest/frame_codec.h"
#include "ingest/frame_ingest.h"
#include "wire/datagram_envelope.h"
#include "wire/key_file.h"
#include "io/trajectory_file.h"
#include "recon/known_correspondences.h"
#include "recon/reconstructor.h"
#include "recon/triangulation.h"
#include "simcore/motion_volume.h"
#include "simcore/projector.h"
#include "simcore/ring_rig.h"
#include "simcore/synthetic_motion.h"
#include "track/gap_filler.h"
#include "track/tracker.h"

namespace mocap {
namespace {

struct BenchArgs {
  int cameras = 16;
  int markers = 60;
  double rate_hz = 240.0;
  int frames = 2400;
  std::string matcher = "relaxation";
  bool no_predictions = false;
  bool contested_groups = false;
  ProjectOptions faults;
  bool json = false;
  bool ingest = false;
  std::string motion;  // a TRC or C3D file instead of the synthetic motion
  int threads = 1;
  bool table = false;
  std::vector<int> table_cameras = {8, 16, 32, 64};
  std::vector<int> table_markers = {40, 60, 100, 150};
};

using Clock = std::chrono::steady_clock;

double Microseconds(Clock::duration d) {
  return std::chrono::duration<double, std::micro>(d).count();
}

// CPU time of this thread: the figure for "one core", unaffected by other processes competing
// for the machine (wall-clock time is reported beside it).
double ThreadCpuMicroseconds() {
  timespec now;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return 1e6 * static_cast<double>(now.tv_sec) + 1e-3 * static_cast<double>(now.tv_nsec);
}

struct Timings {
  std::vector<double> per_frame_us;
  double Mean() const {
    double sum = 0.0;
    for (double t : per_frame_us) sum += t;
    return per_frame_us.empty() ? 0.0 : sum / per_frame_us.size();
  }
  double Percentile(double q) const {
    if (per_frame_us.empty()) return 0.0;
    std::vector<double> sorted = per_frame_us;
    const size_t k = std::min(sorted.size() - 1, static_cast<size_t>(q * sorted.size()));
    std::nth_element(sorted.begin(), sorted.begin() + k, sorted.end());
    return sorted[k];
  }
};

// The simulated session as the nodes would send it, through FrameIngest once per wire mode.
void RunIngestBench(const BenchArgs& args, const Rig& rig, FaultyProjector& projector, const MarkerTrajectories& motion) {
  namespace fs = std::filesystem;
  std::vector<uint32_t> ids;
  for (const Camera& c : rig.cameras) ids.push_back(c.id);
  const fs::path keys = fs::temp_directory_path() / ("mocap_bench_keys_" + std::to_string(::getpid()));
  fs::remove_all(keys);
  fs::create_directories(keys);
  std::map<uint32_t, wire::WireKey> key_of;
  for (uint32_t id : ids) {
    wire::KeyFile f;
    f.node_id = id;
    f.keys.push_back({1, wire::GenerateKey()});
    wire::WriteKeyFile((keys / wire::KeyFileName(id)).string(), f);
    key_of[id] = f.keys[0].key;
  }
  // Datagrams in arrival order, each with its receive time on the session's grid.
  struct Item {
    std::vector<uint8_t> plain, sealed;
    uint64_t receive_ns;
  };
  std::vector<Item> items;
  std::vector<Eigen::Vector3d> truth(motion.NumMarkers());
  std::vector<int> seeing;
  std::map<uint32_t, uint64_t> counters;
  const uint64_t start = RealtimeNowNs();
  const uint64_t period = static_cast<uint64_t>(1e9 / args.rate_hz);
  size_t payload_bytes = 0;
  for (size_t f = 0; f < motion.NumFrames(); ++f) {
    for (size_t m = 0; m < motion.NumMarkers(); ++m) truth[m] = motion.At(f, m);
    for (const CameraFrame& camera : projector.Project(motion.frame_numbers[f], 0, truth.data(), &seeing)) {
      for (auto& packet : EncodeCameraFrame(camera)) {
        const uint64_t t = start + f * period + items.size() % 64 * 1000;
        uint64_t& counter = counters[camera.camera_id];
        counter = wire::NextCounter(counter, t);
        payload_bytes += packet.size();
        std::vector<uint8_t> sealed = wire::SealEnvelope({wire::Direction::kToHub, 1, camera.camera_id, counter},
                                                         key_of[camera.camera_id], packet.data(), packet.size());
        items.push_back({std::move(packet), std::move(sealed), t});
      }
    }
  }
  FrameSetAssemblerOptions assembly;
  assembly.rate_hz = args.rate_hz;
  assembly.deadline_ns = 20'000'000;
  nlohmann::json report = {{"cameras", args.cameras}, {"markers", args.markers}, {"frames", motion.NumFrames()},
                           {"datagrams", items.size()}, {"mean_payload_bytes", double(payload_bytes) / items.size()}};
  double insecure_us = 0.0;
  for (bool authenticated : {false, true}) {
    WireAuthOptions auth;
    if (authenticated) auth.keys_dir = keys.string();
    else auth.insecure_dev = true;
    FrameIngest ingest(ids, assembly, auth);
    Datagram d;
    size_t sets = 0, refused = 0;
    const double cpu_start = ThreadCpuMicroseconds();
    for (const Item& item : items) {
      d.bytes = authenticated ? item.sealed : item.plain;
      d.receive_time_ns = item.receive_ns;
      refused += !ingest.Add(d, nullptr).ok;
      sets += ingest.Collect(item.receive_ns).size();
    }
    sets += ingest.Flush().size();
    const double us = ThreadCpuMicroseconds() - cpu_start;
    const double per = us / items.size();
    if (!authenticated) insecure_us = per;
    report[authenticated ? "authenticated" : "insecure"] = {
        {"us_per_datagram", per}, {"datagrams_per_s", 1e6 / per}, {"frame_sets", sets}, {"refused", refused}};
    if (refused) throw std::runtime_error("bench --ingest: " + std::to_string(refused) + " datagrams refused");
  }
  fs::remove_all(keys);
  const double auth_us = report["authenticated"]["us_per_datagram"].get<double>();
  report["auth_cost_us_per_datagram"] = auth_us - insecure_us;
  if (args.json) {
    std::printf("%s\n", report.dump().c_str());
    return;
  }
  std::printf("bench --ingest: %d cameras, %d markers, %zu frames: %zu datagrams (%.0f B packets on average)\n",
              args.cameras, args.markers, motion.NumFrames(), items.size(), double(payload_bytes) / items.size());
  std::printf("%-34s %12s %14s %12s\n", "ingest (thread CPU)", "us/datagram", "datagrams/s", "frame sets");
  for (const char* mode : {"insecure", "authenticated"})
    std::printf("%-34s %12.2f %14.0f %12zu\n",
                std::string(mode) == "insecure" ? "insecure development wire" : "authenticated (HMAC-SHA-512/256)",
                report[mode]["us_per_datagram"].get<double>(), report[mode]["datagrams_per_s"].get<double>(),
                report[mode]["frame_sets"].get<size_t>());
  std::printf("authentication adds %.2f us per datagram\n", auth_us - insecure_us);
}

// One timed run of reconstruct + track over a motion, beside the floor.
struct CaseResult {
  int cameras = 0;
  size_t markers = 0, frames = 0;
  double blobs_per_frame = 0.0;
  Timings pipeline, floor, pipeline_wall, floor_wall;
  double first_frame_us = 0.0;  // the cold start, wall clock: included in the timings above
  double points_per_frame = 0.0, floor_points_per_frame = 0.0, output_samples_per_frame = 0.0;
  double leftover_per_frame = 0.0;
  double served_again_per_frame = 0.0;
  double group_points_per_frame = 0.0;
  double matcher_frames = 0.0;  // share of frames that left blobs to the matcher
  int output_markers = 0;
  ReconstructionStageTimes stages;
};

CaseResult RunCase(const BenchArgs& args, const MarkerTrajectories& motion, const Rig& rig) {
  FaultyProjector projector(rig, motion.NumMarkers(), args.faults);
  ReconstructorOptions recon_options;
  recon_options.matcher = MatcherTypeFromString(args.matcher);
  recon_options.use_predictions = !args.no_predictions;
  recon_options.prediction.resolve_contested_groups = args.contested_groups;
  recon_options.threads = args.threads;
  Reconstructor reconstructor(rig, recon_options);
  TrackerOptions tracker_options;
  tracker_options.rate_hz = motion.rate_hz;
  Tracker tracker(tracker_options);
  size_t output_samples = 0;
  GapFiller filler(GapFillOptions(), [&](uint64_t, const std::vector<TrackSample>& row) {
    output_samples += row.size();
  });
  const RigModel floor_rig(rig);
  FrameViews floor_views, truth_views;
  std::vector<std::vector<int>> true_views;
  std::vector<Eigen::Vector3d> floor_positions;

  CaseResult result;
  result.cameras = static_cast<int>(rig.cameras.size());
  result.markers = motion.NumMarkers();
  result.frames = motion.NumFrames();
  FrameSet frame_set;
  std::vector<int> seeing;
  std::vector<ReconstructedPoint> points;
  std::vector<TrackSample> samples;
  std::vector<Eigen::Vector3d> truth(motion.NumMarkers());
  size_t blobs = 0, floor_points = 0, pipeline_points = 0;
  for (size_t f = 0; f < motion.NumFrames(); ++f) {
    const uint64_t frame_number = motion.frame_numbers[f];
    for (size_t m = 0; m < motion.NumMarkers(); ++m) truth[m] = motion.At(f, m);
    frame_set.frame_number = frame_number;
    frame_set.cameras = projector.Project(frame_number, 0, truth.data(), &seeing);
    for (const CameraFrame& camera : frame_set.cameras) blobs += camera.blobs.size();
    // The true views are found outside the timing; the floor times undistortion and one robust
    // triangulation per marker, no matching.
    BuildFrameViews(floor_rig, frame_set, &truth_views);
    FindTrueViews(floor_rig, truth_views, truth, KnownCorrespondenceOptions(), &true_views);
    const Clock::time_point floor_start = Clock::now();
    const double floor_cpu_start = ThreadCpuMicroseconds();
    BuildFrameViews(floor_rig, frame_set, &floor_views);
    floor_points += TriangulateKnownCorrespondences(floor_rig, floor_views, true_views, TriangulationOptions(),
                                                    &floor_positions);
    result.floor.per_frame_us.push_back(ThreadCpuMicroseconds() - floor_cpu_start);
    result.floor_wall.per_frame_us.push_back(Microseconds(Clock::now() - floor_start));

    const Clock::time_point start = Clock::now();
    const double cpu_start = ThreadCpuMicroseconds();
    reconstructor.Process(frame_set, tracker.Predict(frame_number), &points);
    tracker.FollowPointNoise(reconstructor.point_noise_mm());
    samples.clear();
    tracker.Update(frame_number, points, &samples);
    filler.Add(frame_number, samples);
    result.pipeline.per_frame_us.push_back(ThreadCpuMicroseconds() - cpu_start);
    result.pipeline_wall.per_frame_us.push_back(Microseconds(Clock::now() - start));
    pipeline_points += points.size();
  }
  filler.Finish();
  const double frames = static_cast<double>(motion.NumFrames());
  result.blobs_per_frame = blobs / frames;
  result.first_frame_us = result.pipeline_wall.per_frame_us.front();
  result.points_per_frame = pipeline_points / frames;
  result.floor_points_per_frame = floor_points / frames;
  result.output_samples_per_frame = output_samples / frames;
  result.leftover_per_frame = reconstructor.stats().leftover_observations / frames;
  result.served_again_per_frame = reconstructor.stats().predictions_served_again / frames;
  result.group_points_per_frame = reconstructor.stats().points_from_contested_groups / frames;
  result.matcher_frames = reconstructor.stats().matcher_runs / frames;
  result.output_markers = tracker.NumMarkers();
  result.stages = reconstructor.stage_times();
  return result;
}

// With several threads the calling thread's CPU time no longer measures the work: wall clock
// is the figure then (on a quiet machine).
const Timings& PipelineTimes(const BenchArgs& args, const CaseResult& r) {
  return args.threads > 1 ? r.pipeline_wall : r.pipeline;
}

nlohmann::json CaseJson(const BenchArgs& args, const CaseResult& r) {
  const Timings& pipeline = PipelineTimes(args, r);
  const double period_us = 1e6 / args.rate_hz;
  const double frames = static_cast<double>(r.frames);
  const double mean = pipeline.Mean(), floor_mean = r.floor.Mean();
  const auto stats = [](const Timings& t) {
    return nlohmann::json{{"mean", t.Mean()}, {"median", t.Percentile(0.5)}, {"p99", t.Percentile(0.99)}, {"max", t.Percentile(1.0)}};
  };
  return {
      {"cameras", r.cameras},
      {"markers", r.markers},
      {"rate_hz", args.rate_hz},
      {"frames", r.frames},
      {"threads", args.threads},
      {"matcher", args.matcher},
      {"predictions", !args.no_predictions},
      {"blobs_per_frame", r.blobs_per_frame},
      {"timing", args.threads > 1 ? "wall" : "thread_cpu"},
      {"reconstruct_track_us", stats(pipeline)},
      {"floor_us", stats(r.floor)},
      {"wall_reconstruct_track_us", {{"mean", r.pipeline_wall.Mean()}, {"median", r.pipeline_wall.Percentile(0.5)}}},
      {"wall_floor_us", {{"mean", r.floor_wall.Mean()}, {"median", r.floor_wall.Percentile(0.5)}}},
      {"first_frame_us", r.first_frame_us},
      {"ratio_to_floor", mean / floor_mean},
      {"real_time_factor", period_us / mean},
      {"floor_real_time_factor", period_us / floor_mean},
      {"p99_over_median", pipeline.Percentile(0.99) / pipeline.Percentile(0.5)},
      {"points_per_frame", r.points_per_frame},
      {"leftover_blobs_per_frame", r.leftover_per_frame},
      {"predictions_served_again_per_frame", r.served_again_per_frame},
      {"contested_group_points_per_frame", r.group_points_per_frame},
      {"matcher_frames_share", r.matcher_frames},
      {"floor_points_per_frame", r.floor_points_per_frame},
      {"output_markers", r.output_markers},
      {"output_samples_per_frame", r.output_samples_per_frame},
      {"stages_us_per_frame",
       {{"views", r.stages.views_us / frames},
        {"index", r.stages.index_us / frames},
        {"predictions", r.stages.predictions_us / frames},
        {"groups", r.stages.groups_us / frames},
        {"matcher", r.stages.matcher_us / frames},
        {"ghosts", r.stages.ghosts_us / frames}}},
  };
}

void PrintCase(const BenchArgs& args, const CaseResult& r, const std::string& motion_name) {
  const Timings& pipeline = PipelineTimes(args, r);
  const double period_us = 1e6 / args.rate_hz;
  const double frames = static_cast<double>(r.frames);
  const double mean = pipeline.Mean(), floor_mean = r.floor.Mean();
  std::printf("bench: %d cameras, %zu markers (%s), %zu frames, real time = %.0f Hz, %.1f blobs/frame, matcher %s%s, "
              "%d thread%s\n",
              r.cameras, r.markers, motion_name.c_str(), r.frames, args.rate_hz, r.blobs_per_frame,
              args.matcher.c_str(), args.no_predictions ? " (no predictions)" : "", args.threads,
              args.threads == 1 ? "" : "s");
  std::printf("%-28s %10s %10s %10s %10s %12s\n",
              args.threads > 1 ? "per frame (us, wall clock)" : "per frame (us, thread CPU)", "mean", "median", "p99",
              "max", "real-time x");
  std::printf("%-28s %10.1f %10.1f %10.1f %10.1f %12.1f\n", "reconstruct + track", mean, pipeline.Percentile(0.5),
              pipeline.Percentile(0.99), pipeline.Percentile(1.0), period_us / mean);
  std::printf("%-28s %10.1f %10.1f %10.1f %10.1f %12.1f\n", "floor (true correspondences)", floor_mean,
              r.floor.Percentile(0.5), r.floor.Percentile(0.99), r.floor.Percentile(1.0), period_us / floor_mean);
  std::printf("wall clock (us): reconstruct + track mean %.1f median %.1f; floor mean %.1f median %.1f; "
              "first frame %.0f\n",
              r.pipeline_wall.Mean(), r.pipeline_wall.Percentile(0.5), r.floor_wall.Mean(),
              r.floor_wall.Percentile(0.5), r.first_frame_us);
  std::printf("ratio to floor %.2f; p99/median %.2f; points/frame %.2f (floor %.2f); %.1f blobs/frame left to the "
              "matcher; %d output markers for %zu\n",
              mean / floor_mean, pipeline.Percentile(0.99) / pipeline.Percentile(0.5), r.points_per_frame,
              r.floor_points_per_frame, r.leftover_per_frame, r.output_markers, r.markers);
  std::printf("stages (us/frame, wall): views %.1f index %.1f predictions %.1f contested groups %.1f matcher %.1f "
              "ghosts %.1f; track the rest; %.2f predictions/frame served again after a parallel attempt\n",
              r.stages.views_us / frames, r.stages.index_us / frames, r.stages.predictions_us / frames,
              r.stages.groups_us / frames, r.stages.matcher_us / frames, r.stages.ghosts_us / frames,
              r.served_again_per_frame);
  std::printf("contested groups: %.2f points/frame; matcher called in %.1f %% of frames\n", r.group_points_per_frame,
              100.0 * r.matcher_frames);
}

MarkerTrajectories SyntheticBenchMotion(const BenchArgs& args, int markers) {
  SyntheticMotionOptions motion_options;
  motion_options.markers = markers;
  motion_options.frames = args.frames;
  motion_options.rate_hz = args.rate_hz;
  return MakeSyntheticMotion(motion_options);
}

Rig BenchRig(const MarkerTrajectories& motion, int cameras) {
  RingRigOptions rig_options;
  rig_options.cameras = cameras;
  return MakeRingRig(ComputeMotionVolume(motion, -1), rig_options);
}

// Cameras x markers on the synthetic motion, one line per case.
void RunTable(const BenchArgs& args) {
  const double period_us = 1e6 / args.rate_hz;
  nlohmann::json rows = nlohmann::json::array();
  if (!args.json) {
    std::printf("bench --table: %d frames per case at %.0f Hz, %d thread%s, %s\n", args.frames, args.rate_hz,
                args.threads, args.threads == 1 ? "" : "s",
                args.threads > 1 ? "wall clock" : "thread CPU time");
    std::printf("%7s %7s %9s %9s %9s %9s %9s %8s %9s %8s %9s %9s\n", "cameras", "markers", "mean us", "median",
                "p99", "max", "first", "RT x", "floor us", "x floor", "p99/med", "out/true");
  }
  for (int cameras : args.table_cameras) {
    for (int markers : args.table_markers) {
      const MarkerTrajectories motion = SyntheticBenchMotion(args, markers);
      const CaseResult r = RunCase(args, motion, BenchRig(motion, cameras));
      if (args.json) {
        rows.push_back(CaseJson(args, r));
        continue;
      }
      const Timings& t = PipelineTimes(args, r);
      std::printf("%7d %7d %9.1f %9.1f %9.1f %9.0f %9.0f %8.1f %9.1f %8.2f %9.2f %5d/%-3d\n", cameras, markers,
                  t.Mean(), t.Percentile(0.5), t.Percentile(0.99), t.Percentile(1.0), r.first_frame_us,
                  period_us / t.Mean(), r.floor.Mean(), t.Mean() / r.floor.Mean(),
                  t.Percentile(0.99) / t.Percentile(0.5), r.output_markers, markers);
      std::fflush(stdout);
    }
  }
  if (args.json) std::printf("%s\n", rows.dump().c_str());
}

void RunBench(BenchArgs args) {
  if (args.cameras < 2) throw UsageError("--cameras must be >= 2");
  if (args.markers < 1) throw UsageError("--markers must be >= 1");
  if (args.frames < 10) throw UsageError("--frames must be >= 10");
  if (!(args.rate_hz > 0.0)) throw UsageError("--rate must be > 0");
  if (args.threads < 1 || args.threads > 256) throw UsageError("--threads must be in [1, 256]");
  for (int c : args.table_cameras) {
    if (c < 2) throw UsageError("--table-cameras: every count must be >= 2");
  }
  for (int m : args.table_markers) {
    if (m < 1) throw UsageError("--table-markers: every count must be >= 1");
  }
  if (args.table && !args.motion.empty()) throw UsageError("--table runs the synthetic motion; drop --motion");
  CheckOptions(args.faults);
  if (args.table) {
    RunTable(args);
    return;
  }

  MarkerTrajectories motion;
  if (args.motion.empty()) {
    motion = SyntheticBenchMotion(args, args.markers);
  } else {
    motion = ReadTrajectories(args.motion);
    if (motion.NumFrames() < 10 || motion.NumMarkers() == 0) {
      throw std::runtime_error(args.motion + ": a bench motion needs at least 10 frames and one marker");
    }
    if (motion.NumFrames() > static_cast<size_t>(args.frames)) {
      motion.frame_numbers.resize(args.frames);
      motion.points.resize(static_cast<size_t>(args.frames) * motion.NumMarkers());
    }
  }
  const Rig rig = BenchRig(motion, args.cameras);
  if (args.ingest) {
    FaultyProjector projector(rig, motion.NumMarkers(), args.faults);
    RunIngestBench(args, rig, projector, motion);
    return;
  }
  const CaseResult result = RunCase(args, motion, rig);
  if (args.json) {
    std::printf("%s\n", CaseJson(args, result).dump().c_str());
    return;
  }
  PrintCase(args, result, args.motion.empty() ? "synthetic" : args.motion);
}

}  // namespace

void AddBenchCommand(CLI::App& app) {
  CLI::App* command = app.add_subcommand("bench", "Time reconstruct + track against the known-correspondence floor");
  auto args = std::make_shared<BenchArgs>();
  args->faults.noise_px = 0.2;
  args->faults.occlusion = 0.05;
  args->faults.occlusion_frames = 5.0;
  args->faults.spurious = 2.0;
  args->faults.drop_frames = 0.002;
  command->add_option("--cameras", args->cameras, "Cameras in the ring")->capture_default_str();
  command->add_option("--markers", args->markers, "Markers of the synthetic motion")->capture_default_str();
  command->add_option("--rate", args->rate_hz, "Frame rate, Hz")->capture_default_str();
  command->add_option("--frames", args->frames, "Frames to simulate and time")->capture_default_str();
  command->add_option("--matcher", args->matcher, "Matcher for untracked blobs")
      ->check(CLI::IsMember({"relaxation", "clustering", "greedy"}))
      ->capture_default_str();
  command->add_flag("--no-predictions", args->no_predictions, "Match every frame from scratch");
  command->add_flag("--contested-groups", args->contested_groups,
                    "Assign contested predictions' groups to blobs per camera (recon/contested_groups.h)");
  command->add_option("--noise-px", args->faults.noise_px, "Centroid noise sigma")->capture_default_str();
  command->add_option("--occlusion", args->faults.occlusion, "Occlusion probability")->capture_default_str();
  command->add_option("--spurious", args->faults.spurious, "False blobs per camera per frame")->capture_default_str();
  command->add_option("--drop-frames", args->faults.drop_frames, "Dropped camera frame probability")->capture_default_str();
  command->add_option("--seed", args->faults.seed, "Fault seed")->capture_default_str();
  command->add_flag("--json", args->json, "One JSON object on stdout");
  command->add_option("--motion", args->motion,
                      "Replay this TRC or C3D motion (its own rate and markers, up to --frames frames) instead of "
                      "the synthetic one; --rate stays the capture rate real time is measured against")
      ->check(CLI::ExistingFile);
  command->add_option("--threads", args->threads, "Worker threads inside a frame (results identical for any count)")
      ->capture_default_str();
  command->add_flag("--table", args->table, "Scaling table: every --table-cameras x --table-markers case");
  command->add_option("--table-cameras", args->table_cameras, "Camera counts of the table")->capture_default_str();
  command->add_option("--table-markers", args->table_markers, "Marker counts of the table")->capture_default_str();
  command->add_flag("--ingest", args->ingest,
                    "Time the hub's datagram ingest instead, authenticated and insecure (datagrams/s)");
  command->callback([args]() { RunBench(*args); });
}

}  // namespace mocap
