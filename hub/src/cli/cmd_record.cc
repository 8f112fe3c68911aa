// `record`: a live session from the nodes over UDP, for scripts: serve's loop
// (service/hub_service.h) run headless, with no API, console or streams, and one capture of its
// own into -o (service/capture.h DirectCapture) that ends the loop at --frames, --duration
// (the kernel's receive time, counted from the bind) or --idle-timeout, or at SIGINT/SIGTERM.
// Every good datagram goes to the session's raw log as received; each frame set the capture
// counts is reconstructed and tracked at once (serve's live reconstruction) and its row written
// and flushed to SESSION/markers.trc, so the TRC grows while the subject moves. Gap filling
// needs hindsight: run `reconstruct` on the session afterwards for the final file.
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
#include "ingest/session.h"
#include "io/marker_trajectories.h"
#include "io/trc.h"
#include "service/hub_service.h"
#include "util/latency_sample.h"
#include "util/log.h"

namespace mocap {
namespace {

std::atomic<bool> g_stop{false};
void OnSignal(int) { g_stop.store(true); }

struct RecordArgs {
  service::ServeOptions options;  // serve's, those record offers; no sessions directory
  std::string output;
  double duration_s = 0.0;
  uint64_t frames = 0;
  double idle_timeout_s = 0.0;
  int max_markers = 64;
  bool no_trc = false;
};

// The live TRC and the latencies, from each frame set the capture counts (on the loop).
class LiveOutputs {
 public:
  explicit LiveOutputs(const RecordArgs& args) {
    for (int i = 0; i < args.max_markers; ++i) names_.push_back(DefaultMarkerName(static_cast<size_t>(i)));
    row_.resize(names_.size());
    if (!args.no_trc)
      trc_.Open((std::filesystem::path(args.output) / "markers.trc").string(), names_, args.options.rate_hz);
  }
  void Add(const FrameSet& set, const pipeline::LiveFrame& frame) {
    for (const CameraFrame& f : set.cameras) {
      if (f.trigger_time_ns && f.send_time_ns >= f.trigger_time_ns)
        trigger_to_send_.Add(double(f.send_time_ns - f.trigger_time_ns) * 1e-6);
      if (f.send_time_ns && frame.publish_ns >= f.send_time_ns)
        send_to_result_.Add(double(frame.publish_ns - f.send_time_ns) * 1e-6);
    }
    if (!trc_.is_open()) return;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::fill(row_.begin(), row_.end(), Eigen::Vector3d(nan, nan, nan));
    for (const TrackSample& s : frame.samples) {
      if (s.frame_number != set.frame_number) continue;  // back-filled frames are already written
      if (s.marker < static_cast<int>(row_.size())) row_[s.marker] = s.position;
      else ++dropped_columns_;
    }
    trc_.WriteFrame(set.frame_number, row_);
  }
  void Close() {
    if (trc_.is_open()) trc_.Close();
  }
  nlohmann::json LatencyJson() const {
    return {{"trigger_to_send_p50", trigger_to_send_.Percentile(50)},
            {"trigger_to_send_p99", trigger_to_send_.Percentile(99)},
            {"send_to_result_p50", send_to_result_.Percentile(50)},
            {"send_to_result_p99", send_to_result_.Percentile(99)}};
  }
  const LatencySample& trigger_to_send() const { return trigger_to_send_; }
  const LatencySample& send_to_result() const { return send_to_result_; }
  uint64_t dropped_columns() const { return dropped_columns_; }

 private:
  TrcWriter trc_;
  std::vector<std::string> names_;
  std::vector<Eigen::Vector3d> row_;
  LatencySample trigger_to_send_, send_to_result_;
  uint64_t dropped_columns_ = 0;
};

void RunRecord(RecordArgs& args) {
  if (args.max_markers < 1 || args.max_markers > 999) throw UsageError("--max-markers must be 1-999");
  service::ServeOptions& options = args.options;
  options.sessions_dir.clear();          // the one capture goes to -o
  options.calibration_monitor = false;   // nobody to tell: record has no API
  if (!options.epoch_ns) options.epoch_ns = RealtimeNowNs();
  CheckOptions(options);
  service::HubService hub(options);
  hub.Bind();

  service::DirectCapture capture;
  capture.dir = args.output;
  capture.max_frame_sets = args.frames;
  // --duration holds to the kernel's receive time from the bind on.
  if (args.duration_s > 0) capture.end_receive_ns = RealtimeNowNs() + static_cast<uint64_t>(args.duration_s * 1e9);
  capture.idle_ns = static_cast<uint64_t>(args.idle_timeout_s * 1e9);
  std::unique_ptr<LiveOutputs> live;  // frames come only once the loop runs
  capture.on_frame = [&live](const FrameSet& set, const pipeline::LiveFrame& frame) { live->Add(set, frame); };
  hub.StartDirectCapture(std::move(capture));  // refuses a directory holding a session
  live = std::make_unique<LiveOutputs>(args);   // so markers.trc is opened only in a new session
  // A capture that fails (a full disk) ends the recording too.
  hub.SubscribeCaptures([](const pipeline::CaptureEvent& e) {
    if (e.kind == pipeline::CaptureEvent::Kind::kStopped) g_stop.store(true);
  });

  std::signal(SIGINT, OnSignal);
  std::signal(SIGTERM, OnSignal);
  log::Info("recording on {} (port {}) into {}; Ctrl-C stops", options.listen, hub.port(), args.output);
  hub.Run(g_stop);
  live->Close();

  const nlohmann::json& summary = hub.last_capture();
  if (summary.value("state", "") != "complete")
    throw std::runtime_error(args.output + ": the recording failed: " + summary.value("reason", "unknown"));
  // record's figures beside the capture's counts.
  SessionInfo info = LoadSessionInfo(args.output);
  const FrameIngest& ingest = hub.ingest();
  info.extra["latency_ms"] = live->LatencyJson();
  info.extra["unauthentic_datagrams"] = ingest.stats().unauthentic;
  info.extra["wire"] = ingest.auth().StatusJson();
  info.extra["incomplete_frame_sets"] = ingest.assembler().incomplete_sets();
  SaveSessionInfo(info, args.output);

  log::Info("per-node statistics:\n{}", ingest.stats().Report());
  if (ingest.auth().rejected_total())
    log::Warn("wire: {} datagrams refused: {}", ingest.auth().rejected_total(),
              ingest.auth().StatusJson()["rejected_by_kind"].dump());
  if (live->dropped_columns())
    log::Warn("{} samples beyond --max-markers {} columns not in the live TRC", live->dropped_columns(),
              args.max_markers);
  std::printf("%s: %llu frame sets, %llu incomplete; latency trigger->send p50 %.2f ms p99 %.2f ms, "
              "send->3D p50 %.2f ms p99 %.2f ms\n",
              args.output.c_str(), static_cast<unsigned long long>(info.frame_sets),
              static_cast<unsigned long long>(ingest.assembler().incomplete_sets()),
              live->trigger_to_send().Percentile(50), live->trigger_to_send().Percentile(99),
              live->send_to_result().Percentile(50), live->send_to_result().Percentile(99));
}

}  // namespace

void AddRecordCommand(CLI::App& app) {
  CLI::App* command = app.add_subcommand("record", "Record a live session from the nodes (UDP): serve's loop, headless, into one directory");
  auto args = std::make_shared<RecordArgs>();
  command->add_option("--listen", args->options.listen, "HOST:PORT to receive on")->capture_default_str();
  command->add_option("--calibration", args->options.calibration, "Calibration JSON (names the cameras)")
      ->required()
      ->check(CLI::ExistingFile);
  command->add_option("-o,--output", args->output, "Session directory to write")->required();
  // Numbers are checked here: a zero, negative or NaN duration or frame count would run forever.
  auto* duration = command->add_option("--duration", args->duration_s, "Stop after S seconds")
                       ->check(FiniteRange(1e-3, 1e7));
  command->add_option("--frames", args->frames, "Stop after N frame sets")
      ->check(CLI::Range(uint64_t{1}, uint64_t{1} << 40))
      ->excludes(duration);
  command->add_option("--rate", args->options.rate_hz, "Trigger rate, Hz")
      ->check(FiniteRange(0.1, 1000.0))
      ->capture_default_str();
  command->add_option("--epoch-ns", args->options.epoch_ns, "Session epoch (time of frame 0), ns; default now")
      ->check(CLI::Range(uint64_t{1}, uint64_t{1} << 62));
  command->add_option("--announce", args->options.announce, "Broadcast HubAnnounce to BROADCAST:PORT every second");
  command->add_option("--keys", args->options.auth.keys_dir,
                      "Directory of the nodes' wire keys (node-N.key); required unless --insecure-dev-wire")
      ->check(CLI::ExistingDirectory);
  command->add_flag("--insecure-dev-wire", args->options.auth.insecure_dev,
                    "DEVELOPMENT ONLY: no keys, unauthenticated datagrams");
  command->add_option("--deadline-ms", args->options.deadline_ms, "How long a frame set waits for late cameras")
      ->check(FiniteRange(0.1, 1000.0))
      ->capture_default_str();
  command->add_flag("--free-run", args->options.free_run, "No trigger wire: group frames by capture time");
  command->add_option("--idle-timeout", args->idle_timeout_s, "Stop after S seconds without datagrams")
      ->check(FiniteRange(0.0, 1e7));
  command->add_option("--max-markers", args->max_markers, "Columns of the live TRC")->capture_default_str();
  command->add_flag("--no-trc", args->no_trc,
                    "No live markers.trc (the session is recorded and reconstructed live all the same)");
  command->callback([args] { RunRecord(*args); });
}

}  // namespace mocap
