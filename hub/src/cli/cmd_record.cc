// `record`: a live session from the nodes over UDP. Every good datagram goes to the session's
// raw log as received; each assembled frame set is reconstructed and tracked at once and its row
// written and flushed to SESSION/markers.trc, so the TRC grows while the subject moves. Gap
// filling needs hindsight: run `reconstruct` on the session afterwards for the final file.
#include <algorithm>
#include <atomic>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "ingest/recorder.h"
#include "ingest/session.h"
#include "ingest/udp_socket.h"
#include "io/calibration_json.h"
#include "io/marker_trajectories.h"
#include "io/trc.h"
#include "pipeline/live_reconstruction.h"
#include "util/latency_sample.h"
#include "util/log.h"

namespace mocap {
namespace {

std::atomic<bool> g_stop{false};
void OnSignal(int) { g_stop.store(true); }

struct RecordArgs {
  std::string listen = "0.0.0.0:30000";
  std::string calibration;
  std::string output;
  double duration_s = 0.0;
  uint64_t frames = 0;
  double rate_hz = 240.0;
  uint64_t epoch_ns = 0;
  std::string announce;
  double deadline_ms = 20.0;
  bool free_run = false;
  double idle_timeout_s = 0.0;
  int max_markers = 64;
  bool no_trc = false;
  WireAuthOptions auth;
};

void RunRecord(const RecordArgs& args) {
  const Rig rig = LoadRigJson(args.calibration);
  if (rig.cameras.size() < 2) throw std::runtime_error(args.calibration + ": needs at least 2 cameras");
  if (args.max_markers < 1 || args.max_markers > 999) throw UsageError("--max-markers must be 1-999");

  RecorderOptions options;
  options.listen = args.listen;
  for (const Camera& c : rig.cameras) options.cameras.push_back(c.id);
  options.image_sizes = ImageSizesOf(rig);
  options.rate_hz = args.rate_hz;
  options.epoch_ns = args.epoch_ns ? args.epoch_ns : RealtimeNowNs();
  options.announce = args.announce;
  options.duration_s = args.duration_s;
  options.max_frames = args.frames;
  options.idle_timeout_s = args.idle_timeout_s;
  options.assembly.deadline_ns = static_cast<uint64_t>(args.deadline_ms * 1e6);
  options.assembly.free_run = args.free_run;
  options.assembly.rate_hz = args.rate_hz;
  options.assembly.epoch_ns = options.epoch_ns;
  options.auth = args.auth;
  CheckOptions(options);
  if (options.auth.insecure_dev)
    log::Warn("INSECURE WIRE: --insecure-dev-wire is set: datagrams are not authenticated; development only");
  Recorder recorder(options);
  recorder.Bind();

  SessionInfo info;
  info.rate_hz = args.rate_hz;
  info.epoch_ns = options.epoch_ns;
  info.free_run = args.free_run;
  info.camera_ids = options.cameras;
  info.source = "record";
  SessionWriter session;
  session.Create(args.output, info);
  std::filesystem::copy_file(args.calibration, std::filesystem::path(args.output) / info.calibration,
                             std::filesystem::copy_options::overwrite_existing);

  pipeline::LiveReconstruction live(rig, args.rate_hz);
  TrcWriter trc;
  std::vector<std::string> names;
  for (int i = 0; i < args.max_markers; ++i) names.push_back(DefaultMarkerName(static_cast<size_t>(i)));
  if (!args.no_trc) trc.Open((std::filesystem::path(args.output) / "markers.trc").string(), names, args.rate_hz);

  std::signal(SIGINT, OnSignal);
  std::signal(SIGTERM, OnSignal);
  log::Info("recording on {} (port {}) from {} cameras into {}; Ctrl-C stops", args.listen, recorder.port(),
            options.cameras.size(), args.output);

  std::vector<Eigen::Vector3d> row(names.size());
  LatencySample trigger_to_send, send_to_result;
  uint64_t dropped_columns = 0;
  recorder.Run(&session, [&](const FrameSet& set) {
    const pipeline::LiveFrame& frame = live.Process(set, RealtimeNowNs);
    const uint64_t done_ns = frame.publish_ns;
    for (const CameraFrame& f : set.cameras) {
      if (f.trigger_time_ns && f.send_time_ns >= f.trigger_time_ns)
        trigger_to_send.Add(double(f.send_time_ns - f.trigger_time_ns) * 1e-6);
      if (f.send_time_ns && done_ns >= f.send_time_ns) send_to_result.Add(double(done_ns - f.send_time_ns) * 1e-6);
    }
    if (!trc.is_open()) return;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::fill(row.begin(), row.end(), Eigen::Vector3d(nan, nan, nan));
    for (const TrackSample& s : frame.samples) {
      if (s.frame_number != set.frame_number) continue;  // back-filled frames are already written
      if (s.marker < static_cast<int>(row.size())) row[s.marker] = s.position;
      else ++dropped_columns;
    }
    trc.WriteFrame(set.frame_number, row);
  }, &g_stop);
  if (trc.is_open()) trc.Close();

  SessionInfo& out = session.info();
  const IngestStats& stats = recorder.stats();
  const IngestTotals totals = stats.Totals();
  out.camera_frames = totals.frames;
  out.dropped_camera_frames = totals.dropped_frames;
  out.extra["off_clock_frames"] = totals.off_clock_frames;
  out.extra["rescaled_frames"] = totals.rescaled_frames;
  out.extra["wrong_size_frames"] = totals.wrong_size_frames;
  out.extra["latency_ms"] = {{"trigger_to_send_p50", trigger_to_send.Percentile(50)},
                             {"trigger_to_send_p99", trigger_to_send.Percentile(99)},
                             {"send_to_result_p50", send_to_result.Percentile(50)},
                             {"send_to_result_p99", send_to_result.Percentile(99)}};
  out.extra["malformed_datagrams"] = stats.malformed;
  out.extra["unauthentic_datagrams"] = stats.unauthentic;
  out.extra["wire"] = recorder.auth().StatusJson();
  out.extra["incomplete_frame_sets"] = recorder.assembler().incomplete_sets();
  out.frame_sets = recorder.frame_sets();
  session.Finish();

  log::Info("per-node statistics:\n{}", stats.Report());
  if (recorder.auth().rejected_total())
    log::Warn("wire: {} datagrams refused: {}", recorder.auth().rejected_total(),
              recorder.auth().StatusJson()["rejected_by_kind"].dump());
  if (dropped_columns)
    log::Warn("{} samples beyond --max-markers {} columns not in the live TRC", dropped_columns, args.max_markers);
  std::printf("%s: %llu frame sets, %llu incomplete; latency trigger->send p50 %.2f ms p99 %.2f ms, "
              "send->3D p50 %.2f ms p99 %.2f ms\n",
              args.output.c_str(), static_cast<unsigned long long>(recorder.frame_sets()),
              static_cast<unsigned long long>(recorder.assembler().incomplete_sets()),
              trigger_to_send.Percentile(50), trigger_to_send.Percentile(99), send_to_result.Percentile(50),
              send_to_result.Percentile(99));
}

}  // namespace

void AddRecordCommand(CLI::App& app) {
  CLI::App* command = app.add_subcommand("record", "Record a live session from the nodes (UDP)");
  auto args = std::make_shared<RecordArgs>();
  command->add_option("--listen", args->listen, "HOST:PORT to receive on")->capture_default_str();
  command->add_option("--calibration", args->calibration, "Calibration JSON (names the cameras)")
      ->required()
      ->check(CLI::ExistingFile);
  command->add_option("-o,--output", args->output, "Session directory to write")->required();
  // Numbers are checked here: a zero, negative or NaN duration or frame count would run forever.
  auto* duration = command->add_option("--duration", args->duration_s, "Stop after S seconds")
                       ->check(FiniteRange(1e-3, 1e7));
  command->add_option("--frames", args->frames, "Stop after N frame sets")
      ->check(CLI::Range(uint64_t{1}, uint64_t{1} << 40))
      ->excludes(duration);
  command->add_option("--rate", args->rate_hz, "Trigger rate, Hz")->check(FiniteRange(0.1, 10000.0))->capture_default_str();
  command->add_option("--epoch-ns", args->epoch_ns, "Session epoch (time of frame 0), ns; default now")
      ->check(CLI::Range(uint64_t{1}, uint64_t{1} << 62));
  command->add_option("--announce", args->announce, "Broadcast HubAnnounce to BROADCAST:PORT every second");
  command->add_option("--keys", args->auth.keys_dir,
                      "Directory of the nodes' wire keys (node-N.key); required unless --insecure-dev-wire")
      ->check(CLI::ExistingDirectory);
  command->add_flag("--insecure-dev-wire", args->auth.insecure_dev,
                    "DEVELOPMENT ONLY: no keys, unauthenticated datagrams");
  command->add_option("--deadline-ms", args->deadline_ms, "How long a frame set waits for late cameras")
      ->check(FiniteRange(0.1, 10000.0))
      ->capture_default_str();
  command->add_flag("--free-run", args->free_run, "No trigger wire: group frames by capture time");
  command->add_option("--idle-timeout", args->idle_timeout_s, "Stop after S seconds without datagrams")
      ->check(FiniteRange(0.0, 1e7));
  command->add_option("--max-markers", args->max_markers, "Columns of the live TRC")->capture_default_str();
  command->add_flag("--no-trc", args->no_trc, "Only record; no live reconstruction");
  command->callback([args] { RunRecord(*args); });
}

}  // namespace mocap
