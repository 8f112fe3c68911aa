// The live hub (`mocap-hub serve`): one UDP socket to the nodes and one loop thread that owns all
// state. Every datagram goes through FrameIngest (logged into the running capture), then to the
// node registry (status, traffic), the control requests (acks) or the preview assembler; every
// frame set is reconstructed and tracked at once and published to the subscribers; controls,
// previews, automatic masks and captures are requested from any thread and run on the loop.
//
// Threads: Run() is the loop. The public request methods may be called from any other thread
// (the HTTP server's); they hand work to the loop and wait for its answer, never longer than the
// request timeout plus a margin. Subscribers are called on the loop thread and must return at
// once (copy the frame and queue it).
//
// Error policy: bad options throw std::invalid_argument from the constructor; a request the
// service cannot honour throws ApiError with the HTTP status that says whose fault it was (4xx:
// the request, 504: a node that did not answer, 5xx: ours); outside input never throws.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "geometry/camera.h"
#include "ingest/frame_ingest.h"
#include "ingest/udp_socket.h"
#include "pipeline/live_reconstruction.h"
#include "pipeline/live_skeleton.h"
#include "service/api_error.h"
#include "service/auto_mask.h"
#include "service/auto_mask_job.h"
#include "service/capture.h"
#include "service/control_requests.h"
#include "service/calibration_monitor.h"
#include "service/live_subscribers.h"
#include "service/live_wanding.h"
#include "service/node_registry.h"
#include "service/preview_assembler.h"
#include "service/processing_jobs.h"
#include "service/published_statistics.h"
#include "service/serve_options.h"
#include "service/service_api.h"
#include "service/waiters.h"
#include "service/wand_collection.h"

namespace mocap::service {

class HubService : public ServiceApi {
 public:
  using Subscriber = LiveSubscribers::FrameSubscriber;
  using CaptureListener = LiveSubscribers::CaptureListener;

  // Loads the calibration and the mask file; throws std::invalid_argument / std::runtime_error.
  explicit HubService(ServeOptions options);
  ~HubService() override;

  // Binds the UDP socket (so callers learn the port before nodes start).
  void Bind();
  uint16_t port() const { return socket_.port(); }
  // The loop: runs until stop turns true or a DirectCapture reaches its limits; a capture still
  // running is finished. on_turn (if set) is called once per loop turn with the time (a
  // watchdog proves the loop is alive).
  void Run(const std::atomic<bool>& stop, const std::function<void(uint64_t)>& on_turn = nullptr);

  // `record`: this loop run headless with one capture into a directory it names, started before
  // Run (the loop owns the captures once it runs) and ending the loop at its limits. Throws
  // ApiError as StartCapture does.
  void StartDirectCapture(DirectCapture capture) {
    captures_.StartDirect(std::move(capture), ingest_.stats(), RealtimeNowNs());
  }
  // Before Run or after it returned (the loop's thread owns them meanwhile): the ingest's
  // counts, and the last capture that ended (summary with "state" and "frame_sets").
  const FrameIngest& ingest() const { return ingest_; }
  const nlohmann::json& last_capture() const { return captures_.last(); }

  // ---- requests from other threads (each waits for the loop) ----
  nlohmann::json Status() override;
  nlohmann::json Nodes() override;
  nlohmann::json Node(uint32_t node_id) override;
  // Every setting given is sent as one request; returns the node's answer.
  nlohmann::json Configure(uint32_t node_id, const CameraSettings& settings) override;
  nlohmann::json Identify(uint32_t node_id, uint32_t duration_ms) override;
  std::vector<uint8_t> PreviewPng(uint32_t node_id, bool thresholded, uint32_t downscale) override;
  // Blobs of `frames` frame sets (the volume must be empty) -> each camera's mask, installed on
  // its node and kept in the mask file. Clear removes every mask.
  nlohmann::json AutoMask(int frames) override;
  nlohmann::json ClearMasks() override;
  nlohmann::json StartCapture(const std::string& name) override;
  nlohmann::json StopCapture() override;
  nlohmann::json Sessions() override;
  nlohmann::json Session(const std::string& name) override;
  nlohmann::json DeleteSession(const std::string& name) override;
  nlohmann::json RenameSession(const std::string& name, const std::string& new_name) override;
  nlohmann::json AnnotateSession(const std::string& name, const std::string& notes) override;
  std::string SessionFile(const std::string& name, const std::string& file) override;
  nlohmann::json Calibration() override;
  // The next frame set's blobs: waits for it at most kBlobsWaitSeconds, and not at all when no
  // frame set came for that long (then "frame" is null), so idle consoles hold no HTTP worker.
  // The loop only copies the set; the JSON is made on the caller's thread.
  nlohmann::json Blobs() override;
  static constexpr double kBlobsWaitSeconds = 0.5;
  // Live wanding: a capture named options.session whose frame sets feed each camera's wand
  // samples and coverage until every camera has enough (or the timeout), then a solve on a
  // worker thread; Apply switches the live reconstruction to the solved calibration (and with
  // save writes it over --calibration, every replaced file kept as CAL.<UTC time>).
  nlohmann::json StartWanding(const WandingOptions& options) override;
  nlohmann::json Wanding() override;
  nlohmann::json StopWanding(bool solve) override;
  nlohmann::json SolveWanding(const std::string& refine_intrinsics) override;
  nlohmann::json ApplyWandCalibration(bool save) override;
  // The monitor's accepted solve of one camera into the live reconstruction (409 without one).
  nlohmann::json ApplyMonitorSolve(uint32_t camera_id, bool save) override;
  // Waits for request.frames frame sets (at most their duration + 2 s), solves on the calling
  // thread, then applies and saves on the loop. 409 while wanding collects; 504 when fewer than
  // 10 frame sets came; 422 when the L-frame (or floor) is not found.
  nlohmann::json SetWorldFrame(const WorldFrameRequest& request) override;
  // 409 while the session is being captured or is not complete; 503 when serve runs no jobs.
  nlohmann::json ProcessSession(const std::string& name, const nlohmann::json& request) override;
  nlohmann::json Processing() override;
  std::string ProcessedFile(const std::string& name, const std::string& recipe, const std::string& file) override;
  nlohmann::json ProcessedEdits(const std::string& name, const std::string& recipe) override;
  nlohmann::json PutProcessedEdits(const std::string& name, const std::string& recipe, const nlohmann::json& log) override;

  // Every published frame, and every capture's start and stop (live_subscribers.h), called on the
  // loop; Unsubscribe takes either's id.
  int Subscribe(Subscriber subscriber) { return subscribers_.AddFrames(std::move(subscriber)); }
  int SubscribeCaptures(CaptureListener listener) { return subscribers_.AddCaptures(std::move(listener)); }
  void Unsubscribe(int id) { subscribers_.Remove(id); }
  // Status() carries section() under `name` (the streams' figures); any thread, any time;
  // section() runs on the loop, so it must be quick and thread-safe.
  void AddStatusSection(const std::string& name, std::function<nlohmann::json()> section);
  void RemoveStatusSection(const std::string& name);

 private:
  // Runs f on the loop thread and returns its result (or rethrows its exception).
  template <typename F>
  auto OnLoop(F f) -> decltype(f());
  template <typename T>
  T Await(std::future<T> future, double seconds);
  void RunTasks();

  void HandleDatagram(const Datagram& datagram);
  void OnOffClockFrame(const v1::MarkerFrame& frame, const Datagram& d);
  void Publish(const FrameSet& set);
  void Tick(uint64_t now_ns);
  void WarnOfSingleCameraSets(uint64_t now_ns);
  // ApiError 409 when a processing job is queued for or running on the session (no rename, delete).
  void RefuseIfProcessing(const std::string& name) const;
  void Announce(uint64_t now_ns);
  void OnRegistryEvents(const std::vector<RegistryEvent>& events);
  void OnRequestFinished(const RequestResult& result);
  // Into the mask job; its last frame set wanted computes the masks and sends them.
  void CollectMaskFrames(const FrameSet& set);
  void FailMaskJob(const std::string& reason, int status);
  std::future<RequestResult> Submit(uint32_t node_id, const std::vector<v1::Control>& commands);
  void SendMask(const CameraMask& mask, uint32_t node_id);
  // Encodes, seals under node_id's key and sends one packet.
  void SendToNode(uint32_t node_id, const HostPort& to, const v1::Packet& packet);
  void WarnAboutMissingKeys() const;
  void SaveMasks();
  const NodeEntry& KnownNode(uint32_t node_id) const;  // throws ApiError 404
  // Ends the wanding's capture, then its collection (409 when none runs).
  void FinishWanding(const std::string& reason, bool solve);
  std::unique_ptr<pipeline::LiveReconstruction> MakeLive() const;
  // Loop only: writes `document` over --calibration (every old file kept as CAL.<UTC time>).
  // Loop only: the live reconstruction (and a fresh monitor) run with `rig` from now on.
  void UseRig(const Rig& rig, const std::string& source);

  ServeOptions options_;
  // The loop thread is the only writer of rig_ (ApplyWandCalibration) and reads it freely; other
  // threads read it under rig_mutex_, which the writer holds while it changes.
  mutable std::mutex rig_mutex_;
  std::mutex edits_mutex_;  // PutProcessedEdits one at a time (hub_service.cc)
  Rig rig_;
  std::string calibration_source_;  // the file rig_ came from
  UdpSocket socket_;
  std::optional<HostPort> announce_to_;
  uint64_t next_announce_ns_ = 0;
  std::map<uint32_t, uint64_t> next_grid_ns_;  // per node: earliest next grid announce (off clock)
  // Frame sets of one camera (nothing 3D in them): warned of at most every 10 s, with the count since.
  uint64_t single_camera_sets_warned_ = 0;
  uint64_t next_single_camera_warning_ns_ = 0;
  uint64_t start_ns_ = 0;
  FrameIngest ingest_;
  NodeRegistry registry_;
  ControlRequests controls_;
  PreviewAssembler previews_;
  std::vector<RigidBodyDefinition> bodies_;
  std::optional<MarkerSet> labels_;
  std::optional<Skeleton> skeleton_;  // --skeleton: solved live (pipeline/live_skeleton.h)
  std::unique_ptr<pipeline::LiveReconstruction> live_;  // made again when the calibration changes
  std::unique_ptr<CalibrationMonitor> calibration_monitor_;  // null when off
  Captures captures_;
  std::unique_ptr<ProcessingJobs> processing_;  // null without options_.processing_executable
  std::vector<CameraMask> masks_;

  // What was published: counts and latencies, their percentiles refreshed from Tick.
  PublishedStatistics published_;

  // Loop-owned: requests waiting for what the nodes send; the automatic mask being made.
  Waiters waiters_;
  std::unique_ptr<AutoMaskJob> mask_job_;
  uint64_t busy_poll_until_ns_ = 0;  // the loop polls without sleeping until then (busy_poll_us)
  uint64_t last_receive_ns_ = 0;     // the newest datagram's receive time: the deadlines' clock in a backlog
  SourceText source_text_;           // the datagrams' "HOST:PORT"

  // Live wanding (loop-owned): the collection while it runs, then its last figures, the solve.
  LiveWanding wanding_;

  // Work handed to the loop by other threads.
  std::mutex tasks_mutex_;
  std::deque<std::function<void()>> tasks_;
  std::atomic<bool> running_{false};

  std::mutex status_sections_mutex_;
  std::map<std::string, std::function<nlohmann::json()>> status_sections_;

  LiveSubscribers subscribers_;
};

}  // namespace mocap::service
