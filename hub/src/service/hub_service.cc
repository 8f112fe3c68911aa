// The live hub's loop and its requests (see hub_service.h).
#include "service/hub_service.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <utility>

#include "io/calibration_json.h"
#include "service/calibration_files.h"
#include "service/hub_json.h"
#include "service/processed_edits.h"
#include "util/json_file.h"
#include "util/log.h"
#include "util/thread_priority.h"
#include "wire/packet.h"

namespace mocap::service {
namespace {

constexpr uint64_t kSecondNs = 1'000'000'000;
// How long a request thread waits for the loop itself (not for a node) before giving up.
constexpr double kLoopAnswerSeconds = 5.0;

uint64_t Ns(double seconds) { return static_cast<uint64_t>(seconds * 1e9); }

}  // namespace

HubService::HubService(ServeOptions options)
    : options_((options.Check(), std::move(options))),
      rig_(LoadServeRig(options_.calibration)),
      calibration_source_(options_.calibration),
      start_ns_(RealtimeNowNs()),
      ingest_(CameraIds(rig_), AssemblyOf(options_, EpochOf(options_)), options_.auth, ImageSizesOf(rig_)),
      registry_(RegistryOf(options_, rig_)),
      controls_(ControlsOf(options_, start_ns_)),
      bodies_(options_.bodies_file.empty() ? std::vector<RigidBodyDefinition>{} : ReadBodiesFile(options_.bodies_file)),
      labels_(options_.labels_file.empty() ? std::optional<MarkerSet>{} : ReadMarkerSetFile(options_.labels_file)),
      skeleton_(options_.skeleton_file.empty() ? std::optional<Skeleton>{} : ReadSkeletonFile(options_.skeleton_file)),
      live_(MakeLive()),
      captures_(options_.sessions_dir, options_.calibration, SessionBase(options_, rig_, EpochOf(options_)),
                options_.disk),
      waiters_(Ns(kBlobsWaitSeconds)) {
  if (!options_.epoch_ns) options_.epoch_ns = start_ns_;
  if (options_.calibration_monitor)
    calibration_monitor_ = std::make_unique<CalibrationMonitor>(rig_, options_.rate_hz, CalibrationMonitorOptions());
  captures_.Lock();
  if (!options_.processing_executable.empty()) {
    ProcessingJobsOptions jobs;
    jobs.executable = options_.processing_executable;
    jobs.sessions_dir = options_.sessions_dir;
    jobs.calibration = options_.calibration;
    jobs.labels = options_.labels_file;
    jobs.bodies = options_.bodies_file;
    processing_ = std::make_unique<ProcessingJobs>(jobs);
  }
  if (options_.auth.insecure_dev)
    log::Warn("INSECURE WIRE: --insecure-dev-wire is set: datagrams are not authenticated, anyone on the network "
              "can forge frames and steer the nodes; for development only (/api/status says so too)");
  else
    WarnAboutMissingKeys();
  for (const std::string& name : captures_.RecoverInterrupted())
    log::Warn("session {} was interrupted (the service stopped during its capture); its raw log is kept", name);
  if (!options_.masks_file.empty() && std::filesystem::exists(options_.masks_file)) {
    masks_ = MasksFromJson(ReadJsonFile(options_.masks_file), options_.masks_file);
    log::Info("{}: masks for {} cameras, sent to each node when it joins", options_.masks_file, masks_.size());
  }
}

HubService::~HubService() = default;

std::unique_ptr<pipeline::LiveReconstruction> HubService::MakeLive() const {
  auto live = std::make_unique<pipeline::LiveReconstruction>(rig_, options_.rate_hz, options_.recon, bodies_, labels_,
                                                             options_.body_filter, options_.tracker);
  if (skeleton_) {
    pipeline::LiveSkeletonOptions o;
    o.name = std::filesystem::path(options_.skeleton_file).stem().string();
    o.up_axis = SkeletonUpAxis(options_.skeleton_up);
    live->AddStage(std::make_unique<pipeline::LiveSkeletonStage>(*skeleton_, labels_->names, o));
  }
  return live;
}

void HubService::WarnAboutMissingKeys() const {
  log::Info("wire authenticated with the keys of {} nodes from {}", ingest_.auth().KeyedNodes().size(),
            options_.auth.keys_dir);
  for (const Camera& c : rig_.cameras)
    if (!ingest_.auth().HasKey(c.id))
      log::Warn("camera {} has no key in {} ({}): its datagrams will be refused", c.id, options_.auth.keys_dir,
                wire::KeyFileName(c.id));
}

void HubService::Bind() {
  socket_.Bind(ParseHostPort(options_.listen));
  if (!options_.announce.empty()) {
    announce_to_ = ParseHostPort(options_.announce);
    socket_.EnableBroadcast();
  }
}

// ---- the loop ----

void HubService::Run(const std::atomic<bool>& stop, const std::function<void(uint64_t)>& on_turn) {
  if (options_.realtime_priority > 0) {
    if (SetThisThreadRealtime(options_.realtime_priority)) {
      log::Info("frame loop under SCHED_FIFO at priority {}", options_.realtime_priority);
    } else {
      log::Warn("frame loop: SCHED_FIFO at priority {} refused (needs root, CAP_SYS_NICE or LimitRTPRIO={} in the "
                "unit); running under the ordinary policy",
                options_.realtime_priority, options_.realtime_priority);
    }
  }
  {
    std::lock_guard<std::mutex> lock(tasks_mutex_);
    running_ = true;
  }
  while (!stop.load() && !captures_.limit_reached()) {
    RunTasks();
    // Wait briefly for the first datagram (not at all while a frame set is arriving and the busy
    // poll lasts), then drain what is queued (bounded, so that tasks and ticks are served under a
    // flood too).
    const int wait_ms = busy_poll_until_ns_ != 0 && RealtimeNowNs() < busy_poll_until_ns_ ? 0 : 1;
    const size_t drained =
        socket_.Drain(wait_ms, UdpSocket::kDrainMax, [this](const Datagram& d) { HandleDatagram(d); });
    const uint64_t now = RealtimeNowNs();
    // Deadlines on the receive clock while datagrams are still queued (a flood, a stalled loop):
    // a set is overdue when its cameras were not received in time, not when the loop came late.
    for (const FrameSet& set : ingest_.Collect(drained == UdpSocket::kDrainMax ? last_receive_ns_ : now)) Publish(set);
    Tick(now);
    subscribers_.NoticeCapture(captures_.running(), captures_.name());
    if (on_turn) on_turn(now);
  }
  for (const FrameSet& set : ingest_.Flush()) Publish(set);
  {
    // Under the queue's lock: no request slips in after the last turn below.
    std::lock_guard<std::mutex> lock(tasks_mutex_);
    running_ = false;
  }
  RunTasks();  // requests queued meanwhile are answered, later ones refused
  if (captures_.running()) {
    try {
      const nlohmann::json summary = captures_.Stop(ingest_.stats(), RealtimeNowNs());
      log::Info("capture {} finished at shutdown: {} frame sets", summary.value("name", ""),
                summary.value("frame_sets", 0));
    } catch (const ApiError& e) {
      log::Error("capture at shutdown: {}", e.what());
    }
  }
  subscribers_.NoticeCapture(captures_.running(), captures_.name());
}

void HubService::RunTasks() {
  std::deque<std::function<void()>> tasks;
  {
    std::lock_guard<std::mutex> lock(tasks_mutex_);
    tasks.swap(tasks_);
  }
  for (auto& task : tasks) task();
}

void HubService::HandleDatagram(const Datagram& d) {
  last_receive_ns_ = std::max(last_receive_ns_, d.receive_time_ns);
  const wire::DecodeResult& decoded = ingest_.Add(d, captures_.WriterFor(d.receive_time_ns));
  const std::string& source = source_text_.Of(d.from);
  if (!decoded.ok) {
    if (ingest_.last_outcome() == IngestOutcome::kUnauthentic)
      registry_.OnUnauthentic(source, decoded.reason, d.receive_time_ns);
    else
      registry_.OnMalformed(source, decoded.reason, d.receive_time_ns);
    return;
  }
  const v1::Packet& packet = decoded.packet;
  if (ingest_.last_outcome() == IngestOutcome::kOffClock) {
    OnOffClockFrame(packet.marker_frame(), d);
    return;
  }
  OnRegistryEvents(registry_.OnPacket(packet, source, d.receive_time_ns));
  if (packet.has_control_ack() && ingest_.IsCamera(packet.control_ack().node_id())) {
    if (auto finished = controls_.OnAck(packet.control_ack(), d.receive_time_ns)) OnRequestFinished(*finished);
  } else if (packet.has_preview_chunk() && ingest_.IsCamera(packet.preview_chunk().node_id())) {
    PreviewImage image;
    if (previews_.Add(packet.preview_chunk(), d.receive_time_ns, &image) == PreviewAssembler::Outcome::kComplete)
      waiters_.Answer(image);
  } else if (packet.has_marker_frame()) {
    // A frame set completes with its last camera's datagram: publish it now, not at the next
    // loop turn. Until then its other cameras' datagrams are awaited without sleeping.
    if (options_.busy_poll_us > 0.0)
      busy_poll_until_ns_ = RealtimeNowNs() + static_cast<uint64_t>(options_.busy_poll_us * 1e3);
    for (const FrameSet& set : ingest_.Collect(d.receive_time_ns)) {
      Publish(set);
      busy_poll_until_ns_ = 0;
    }
  }
}

void HubService::OnOffClockFrame(const v1::MarkerFrame& frame, const Datagram& d) {
  // A node that numbers its frames on another clock (restarted without the session's epoch, or
  // given another one) is sent the session's grid in a Start, which it acknowledges; at most
  // every 2 s per node, so a forger cannot make the hub send much. A node whose own clock is off
  // stays refused: only its clock can fix that, and the warning says so.
  uint64_t& next = next_grid_ns_[frame.node_id()];
  if (d.receive_time_ns < next) return;
  next = d.receive_time_ns + 2 * kSecondNs;
  const NodeStats& stats = ingest_.stats().nodes.at(frame.node_id());
  log::Warn("node {} ({}): frame {} is {:+.3f} s off the session clock ({} refused so far): its epoch or its "
            "clock is wrong; sending it the session's epoch and rate",
            frame.node_id(), d.FromString(), frame.frame_number(), stats.off_clock_s, stats.off_clock_frames);
  v1::Control start;
  start.mutable_start()->set_epoch_ns(options_.epoch_ns);
  start.mutable_start()->set_rate_millihz(static_cast<uint32_t>(std::llround(options_.rate_hz * 1000.0)));
  const SubmitResult submitted = controls_.Submit(frame.node_id(), {start}, RealtimeNowNs());
  if (!submitted.ok) {
    log::Warn("node {}: session grid not sent: {}", frame.node_id(), submitted.error);
    return;
  }
  // To where the frames came from: a node sends and receives on its one control socket.
  const HostPort to = ParseHostPort(d.FromString());
  for (const v1::Packet& packet : submitted.send) SendToNode(frame.node_id(), to, packet);
}

void HubService::Publish(const FrameSet& set) {
  if (mask_job_) CollectMaskFrames(set);
  waiters_.OnFrameSet(set, masks_, RealtimeNowNs());
  const uint64_t start_ns = RealtimeNowNs();
  if (wanding_.collecting()) wanding_.Add(set);
  const pipeline::LiveFrame& frame = live_->Process(set, RealtimeNowNs);
  // The streams first: the bookkeeping below and the capture's live_points.tsv can wait.
  subscribers_.Publish(frame);
  published_.Add(set, frame, rig_.cameras.size(), start_ns);
  if (captures_.running()) captures_.AddPublished(frame, set);
  if (calibration_monitor_) calibration_monitor_->Add(set, live_->reconstructor());
}

void HubService::WarnOfSingleCameraSets(uint64_t now) {
  const uint64_t count = ingest_.assembler().single_camera_sets();
  if (count == single_camera_sets_warned_ || now < next_single_camera_warning_ns_) return;
  log::Warn("{} frame sets held one camera only (nothing in them can be triangulated): the other cameras' frames "
            "came after the {:.0f} ms deadline; the hub machine is overloaded or the network is late",
            count - single_camera_sets_warned_, options_.deadline_ms);
  single_camera_sets_warned_ = count;
  next_single_camera_warning_ns_ = now + 10 * kSecondNs;
}

void HubService::Tick(uint64_t now) {
  WarnOfSingleCameraSets(now);
  captures_.Tick(ingest_.stats(), now);
  published_.Refresh(now);
  Announce(now);
  ingest_.auth().ReloadIfChanged(now);
  OnRegistryEvents(registry_.Tick(now));
  ControlRequests::TickResult tick = controls_.Tick(now);
  for (const v1::Packet& packet : tick.resend) {
    if (const NodeEntry* node = registry_.Find(packet.control().node_id()))
      SendToNode(packet.control().node_id(), ParseHostPort(node->address), packet);
  }
  for (const RequestResult& result : tick.finished) OnRequestFinished(result);
  previews_.DiscardStale(now);
  waiters_.Expire(now, masks_);
  if (wanding_.collecting()) {
    std::string reason = wanding_.StopReason(now);
    // An operator who stops the wanding's capture (capture stop) ends the wanding with it.
    if (reason.empty() && !(captures_.running() && captures_.name() == wanding_.options().session))
      reason = "its capture was stopped";
    if (!reason.empty()) FinishWanding(reason, true);
  }
  wanding_.Poll();
  if (processing_) processing_->Poll();
  if (mask_job_ && mask_job_->TimedOut(now)) FailMaskJob(mask_job_->TimeoutReason(), 504);
}

void HubService::Announce(uint64_t now) {
  if (!announce_to_ || now < next_announce_ns_) return;
  next_announce_ns_ = now + kSecondNs;
  // One announce per node with a key, each sealed for its node (a broadcast reaches them all).
  const std::vector<uint8_t> packet = wire::EncodeHubAnnounce(port(), options_.epoch_ns, options_.rate_hz);
  for (const auto& datagram : ingest_.auth().SealForEveryNode(packet, now)) socket_.SendTo(*announce_to_, datagram);
}

void HubService::OnRegistryEvents(const std::vector<RegistryEvent>& events) {
  for (const RegistryEvent& e : events) {
    log::Info("node {} {} ({})", e.node_id, RegistryEventName(e.kind), e.address);
    const bool fresh = e.kind == RegistryEventKind::kJoined || e.kind == RegistryEventKind::kBack ||
                       e.kind == RegistryEventKind::kRestarted;
    if (!fresh) continue;
    // The installation's mask goes to a node whenever it (re)joins: a restarted node has none.
    for (const CameraMask& mask : masks_)
      if (mask.camera_id == e.node_id) SendMask(mask, e.node_id);
  }
}

void HubService::SendMask(const CameraMask& mask, uint32_t node_id) {
  const SubmitResult submitted = controls_.Submit(node_id, MaskCommands(mask), RealtimeNowNs());
  if (!submitted.ok) {
    log::Warn("mask for node {} not sent: {}", node_id, submitted.error);
    return;
  }
  if (const NodeEntry* node = registry_.Find(node_id)) {
    const HostPort to = ParseHostPort(node->address);
    for (const v1::Packet& packet : submitted.send) SendToNode(node_id, to, packet);
  }
}

void HubService::SendToNode(uint32_t node_id, const HostPort& to, const v1::Packet& packet) {
  const std::vector<uint8_t> datagram = ingest_.auth().Seal(node_id, wire::Encode(packet), RealtimeNowNs());
  if (datagram.empty()) {
    log::Warn("node {}: no key in the keys directory, nothing sent to it", node_id);
    return;
  }
  socket_.SendTo(to, datagram);
}

void HubService::OnRequestFinished(const RequestResult& result) {
  if (result.outcome == RequestOutcome::kRejected || result.outcome == RequestOutcome::kTimedOut)
    log::Warn("node {}: request {}: {}", result.node_id, RequestOutcomeName(result.outcome), result.reason);
  if (waiters_.Answer(result)) return;
  if (!mask_job_ || !mask_job_->Finished(result.request_id, RequestJson(result)) || !mask_job_->AllAnswered()) return;
  // Every node answered: the masks are the installation's now.
  masks_ = mask_job_->masks();
  SaveMasks();
  mask_job_->Succeed(MasksToJson(masks_), options_.masks_file);
  mask_job_.reset();
}

void HubService::CollectMaskFrames(const FrameSet& set) {
  if (!mask_job_->Collect(set)) return;
  const std::vector<CameraMask>& masks =
      mask_job_->ComputeMasks(masks_, [this](uint32_t camera) { return registry_.Find(camera) != nullptr; });
  if (masks.empty()) {  // the job has failed
    mask_job_.reset();
    return;
  }
  const uint64_t now = RealtimeNowNs();
  for (const CameraMask& mask : masks) {
    const SubmitResult submitted = controls_.Submit(mask.camera_id, MaskCommands(mask), now);
    if (!submitted.ok) {
      FailMaskJob("camera " + std::to_string(mask.camera_id) + ": " + submitted.error, 500);
      return;
    }
    const HostPort to = ParseHostPort(registry_.Find(mask.camera_id)->address);
    for (const v1::Packet& packet : submitted.send) SendToNode(mask.camera_id, to, packet);
    mask_job_->Sent(submitted.request_id, mask.camera_id);
  }
}

void HubService::FailMaskJob(const std::string& reason, int status) {
  mask_job_->Fail(status, reason);
  mask_job_.reset();
}

void HubService::SaveMasks() {
  if (options_.masks_file.empty()) return;
  try {
    WriteJsonFile(MasksToJson(masks_), options_.masks_file);
  } catch (const std::exception& e) {
    log::Error("masks not kept: {}", e.what());
  }
}

std::future<RequestResult> HubService::Submit(uint32_t node_id, const std::vector<v1::Control>& commands) {
  const NodeEntry& node = KnownNode(node_id);
  if (node.lost) throw ApiError(409, "node " + std::to_string(node_id) + " is lost (silent since " +
                                         std::to_string((RealtimeNowNs() - node.last_seen_ns) / kSecondNs) + " s)");
  const SubmitResult submitted = controls_.Submit(node_id, commands, RealtimeNowNs());
  if (!submitted.ok) throw ApiError(503, submitted.error);
  const HostPort to = ParseHostPort(node.address);
  for (const v1::Packet& packet : submitted.send) SendToNode(node_id, to, packet);
  return waiters_.ForRequest(submitted.request_id);
}

const NodeEntry& HubService::KnownNode(uint32_t node_id) const {
  const NodeEntry* node = registry_.Find(node_id);
  if (!node) {
    const bool calibrated = ingest_.IsCamera(node_id);
    throw ApiError(404, "no node " + std::to_string(node_id) +
                            (calibrated ? " has been heard from yet" : " (not a camera of the calibration)"));
  }
  return *node;
}

// ---- requests from other threads ----

template <typename F>
auto HubService::OnLoop(F f) -> decltype(f()) {
  using Result = decltype(f());
  auto task = std::make_shared<std::packaged_task<Result()>>(std::move(f));
  std::future<Result> result = task->get_future();
  {
    std::lock_guard<std::mutex> lock(tasks_mutex_);
    if (!running_) throw ApiError(503, "the service is not running");
    tasks_.push_back([task] { (*task)(); });
  }
  return Await(std::move(result), kLoopAnswerSeconds);
}

template <typename T>
T HubService::Await(std::future<T> future, double seconds) {
  if (future.wait_for(std::chrono::duration<double>(seconds)) != std::future_status::ready)
    throw ApiError(504, "no answer within " + std::to_string(static_cast<int>(std::ceil(seconds))) + " s");
  try {
    return future.get();
  } catch (const std::future_error&) {
    throw ApiError(503, "the service stopped before answering");
  }
}

nlohmann::json HubService::Status() {
  return OnLoop([this] {
    const uint64_t now = RealtimeNowNs();
    size_t online = 0;
    const std::vector<NodeEntry> nodes = registry_.Nodes();
    for (const NodeEntry& n : nodes) online += !n.lost;
    nlohmann::json status{
        {"uptime_s", static_cast<double>(now - start_ns_) * 1e-9},
        {"udp_port", port()},
        {"rate_hz", options_.rate_hz},
        {"epoch_ns", options_.epoch_ns},
        {"cameras", rig_.cameras.size()},
        {"nodes_online", online},
        {"nodes_known", nodes.size()},
        {"incomplete_frame_sets", ingest_.assembler().incomplete_sets()},
        {"single_camera_frame_sets", ingest_.assembler().single_camera_sets()},
        {"late_frames", ingest_.assembler().late_frames()},
        {"markers_confirmed", live_->tracker().NumMarkers()},
        {"malformed_datagrams", registry_.malformed_total()},
        {"unknown_datagrams", registry_.unknown_total()},
        {"unauthentic_datagrams", registry_.unauthentic_total()},
        {"wire", ingest_.auth().StatusJson()},
        {"capture", captures_.Current(now)},
        {"last_capture", captures_.last()},
        {"sessions_disk", captures_.Disk()},
        {"masks", CountMaskedCameras(masks_, rig_)},
        {"requests_pending", controls_.pending()},
        {"calibration_monitor", calibration_monitor_ ? calibration_monitor_->StatusJson() : nlohmann::json(nullptr)},
    };
    published_.AddTo(&status);  // the latest snapshot: a few numbers, whatever the reservoirs hold
    std::lock_guard<std::mutex> lock(status_sections_mutex_);
    for (const auto& [name, section] : status_sections_) status[name] = section();
    return status;
  });
}

void HubService::AddStatusSection(const std::string& name, std::function<nlohmann::json()> section) {
  std::lock_guard<std::mutex> lock(status_sections_mutex_);
  status_sections_[name] = std::move(section);
}

void HubService::RemoveStatusSection(const std::string& name) {
  std::lock_guard<std::mutex> lock(status_sections_mutex_);
  status_sections_.erase(name);
}

nlohmann::json HubService::Nodes() {
  return OnLoop([this] {
    nlohmann::json list = nlohmann::json::array();
    for (const NodeEntry& n : registry_.Nodes()) list.push_back(NodeJson(n, ingest_.stats(), masks_, RealtimeNowNs()));
    return list;
  });
}

nlohmann::json HubService::Node(uint32_t node_id) {
  return OnLoop([this, node_id] { return NodeJson(KnownNode(node_id), ingest_.stats(), masks_, RealtimeNowNs()); });
}

nlohmann::json HubService::Configure(uint32_t node_id, const CameraSettings& s) {
  if (s.threshold && (*s.threshold < 1 || *s.threshold > 255)) throw ApiError(400, "threshold must be 1..255");
  if (s.exposure_us && (*s.exposure_us < 1 || *s.exposure_us > 1'000'000))
    throw ApiError(400, "exposure must be 1..1000000 us");
  if (s.gain_milli && (*s.gain_milli < 1000 || *s.gain_milli > 64000))
    throw ApiError(400, "gain must be 1000..64000 (thousandths: 1x..64x)");
  if ((s.brightness_pct && *s.brightness_pct > 100) || (s.contrast_pct && *s.contrast_pct > 100))
    throw ApiError(400, "brightness_pct and contrast_pct must be 0..100");
  if (!s.threshold && !s.auto_threshold && !s.exposure_us && !s.gain_milli && !s.brightness_pct && !s.contrast_pct)
    throw ApiError(400, "nothing to set");
  std::future<RequestResult> answer = OnLoop([this, node_id, s] {
    const NodeEntry& node = KnownNode(node_id);
    std::vector<v1::Control> commands;
    if (s.threshold || s.auto_threshold) {
      v1::Control c;
      c.mutable_set_threshold()->set_value(s.threshold.value_or(0));
      c.mutable_set_threshold()->set_automatic(s.auto_threshold);
      commands.push_back(c);
    }
    if (s.exposure_us || s.gain_milli) {
      // The node sets both at once: the one not given keeps the node's current value.
      v1::Control c;
      c.mutable_set_exposure()->set_exposure_us(s.exposure_us.value_or(node.exposure_us));
      c.mutable_set_exposure()->set_gain_milli(s.gain_milli.value_or(node.gain_milli));
      commands.push_back(c);
    }
    if (s.brightness_pct || s.contrast_pct) {
      v1::Control c;
      v1::SetPicture* p = c.mutable_set_picture();
      p->set_set_brightness(s.brightness_pct.has_value());
      p->set_brightness_pct(s.brightness_pct.value_or(0));
      p->set_set_contrast(s.contrast_pct.has_value());
      p->set_contrast_pct(s.contrast_pct.value_or(0));
      commands.push_back(c);
    }
    return Submit(node_id, commands);
  });
  return RequestJson(Await(std::move(answer), options_.request_timeout_s + 1.0));
}

nlohmann::json HubService::Identify(uint32_t node_id, uint32_t duration_ms) {
  if (duration_ms < 100 || duration_ms > 60000) throw ApiError(400, "identify duration must be 100..60000 ms");
  std::future<RequestResult> answer = OnLoop([this, node_id, duration_ms] {
    v1::Control c;
    c.mutable_identify()->set_duration_ms(duration_ms);
    return Submit(node_id, {c});
  });
  return RequestJson(Await(std::move(answer), options_.request_timeout_s + 1.0));
}

std::vector<uint8_t> HubService::PreviewPng(uint32_t node_id, bool thresholded, uint32_t downscale) {
  if (downscale != 1 && downscale != 2 && downscale != 4 && downscale != 8)
    throw ApiError(400, "downscale must be 1, 2, 4 or 8");
  std::future<PreviewImage> image = OnLoop([this, node_id, thresholded, downscale] {
    v1::Control c;
    c.mutable_preview_request()->set_mode(thresholded ? v1::PREVIEW_MODE_THRESHOLDED : v1::PREVIEW_MODE_RAW);
    c.mutable_preview_request()->set_downscale(downscale);
    Submit(node_id, {c});  // the image itself is the answer that counts
    return waiters_.ForPreview(node_id, thresholded, RealtimeNowNs() + Ns(options_.request_timeout_s));
  });
  return EncodePng(Await(std::move(image), options_.request_timeout_s + 1.0));
}

nlohmann::json HubService::AutoMask(int frames) {
  if (frames < 10 || frames > options_.auto_mask_max_frames)
    throw ApiError(400, "frames must be 10.." + std::to_string(options_.auto_mask_max_frames));
  const double collect_s = frames / options_.rate_hz + 2.0;
  std::future<nlohmann::json> answer = OnLoop([this, frames, collect_s] {
    if (mask_job_) throw ApiError(409, "an automatic mask is being made already");
    mask_job_ = std::make_unique<AutoMaskJob>(frames, RealtimeNowNs() + Ns(collect_s));
    return mask_job_->Answer();
  });
  return Await(std::move(answer), collect_s + options_.request_timeout_s + 1.0);
}

nlohmann::json HubService::ClearMasks() {
  std::vector<std::future<RequestResult>> answers = OnLoop([this] {
    std::vector<std::future<RequestResult>> futures;
    for (const CameraMask& mask : masks_) {
      const NodeEntry* node = registry_.Find(mask.camera_id);
      if (!node || node->lost) continue;
      CameraMask empty = mask;
      empty.regions.clear();
      futures.push_back(Submit(mask.camera_id, MaskCommands(empty)));
    }
    masks_.clear();
    SaveMasks();
    return futures;
  });
  nlohmann::json results = nlohmann::json::array();
  for (auto& answer : answers) results.push_back(RequestJson(Await(std::move(answer), options_.request_timeout_s + 1.0)));
  return {{"nodes", results}};
}

nlohmann::json HubService::StartCapture(const std::string& name) {
  return OnLoop([this, name] {
    const uint64_t now = RealtimeNowNs();
    captures_.Start(name, ingest_.stats(), now);
    log::Info("capture {} started", name);
    return captures_.Current(now);
  });
}

nlohmann::json HubService::StopCapture() {
  return OnLoop([this] {
    nlohmann::json summary = captures_.Stop(ingest_.stats(), RealtimeNowNs());
    log::Info("capture {} stopped: {} frame sets", summary.value("name", ""), summary.value("frame_sets", 0));
    return summary;
  });
}

nlohmann::json HubService::Sessions() {
  return OnLoop([this] { return captures_.List(); });
}

nlohmann::json HubService::Session(const std::string& name) {
  return OnLoop([this, name] { return captures_.Describe(name); });
}

void HubService::RefuseIfProcessing(const std::string& name) const {
  if (processing_ && processing_->Uses(name))
    throw ApiError(409, "session '" + name + "' has a processing job queued or running; wait for it");
}

nlohmann::json HubService::DeleteSession(const std::string& name) {
  return OnLoop([this, name] {
    RefuseIfProcessing(name);
    return captures_.Delete(name, RealtimeNowNs());
  });
}

nlohmann::json HubService::RenameSession(const std::string& name, const std::string& new_name) {
  return OnLoop([this, name, new_name] {
    RefuseIfProcessing(name);
    return captures_.Rename(name, new_name);
  });
}

nlohmann::json HubService::AnnotateSession(const std::string& name, const std::string& notes) {
  return OnLoop([this, name, notes] { return captures_.SetNotes(name, notes); });
}

std::string HubService::SessionFile(const std::string& name, const std::string& file) {
  return OnLoop([this, name, file] { return captures_.FilePath(name, file); });
}

nlohmann::json HubService::ProcessSession(const std::string& name, const nlohmann::json& request) {
  if (!processing_) throw ApiError(503, "this serve runs no processing jobs");
  OnLoop([this, name] {
    if (captures_.running() && captures_.name() == name)
      throw ApiError(409, "session '" + name + "' is being captured; stop the capture first");
    const std::string state = captures_.Describe(name).value("state", "");
    if (state != "complete") throw ApiError(409, "session '" + name + "' is " + state + ", not complete");
    return 0;
  });
  return processing_->Start(name, request);
}

nlohmann::json HubService::Processing() {
  if (!processing_) return {{"jobs", nlohmann::json::array()}, {"available", false}};
  nlohmann::json out = processing_->Jobs();
  out["available"] = true;
  return out;
}

std::string HubService::ProcessedFile(const std::string& name, const std::string& recipe, const std::string& file) {
  return OnLoop([this, name, recipe, file] { return captures_.ProcessedFilePath(name, recipe, file); });
}

// The edits run on the caller's thread (an HTTP worker), not the loop: a long take's fill must not
// hold frame sets back. One at a time, so two PUTs never write the same outputs together.
nlohmann::json HubService::ProcessedEdits(const std::string& name, const std::string& recipe) {
  const std::string dir = OnLoop([this, name, recipe] { return captures_.ProcessedDirPath(name, recipe); });
  std::lock_guard<std::mutex> lock(edits_mutex_);
  return ReadProcessedEdits(dir);
}

nlohmann::json HubService::PutProcessedEdits(const std::string& name, const std::string& recipe, const nlohmann::json& log) {
  const std::string dir = OnLoop([this, name, recipe] { return captures_.ProcessedDirPath(name, recipe); });
  std::lock_guard<std::mutex> lock(edits_mutex_);
  return WriteProcessedEdits(dir, log);
}

nlohmann::json HubService::Calibration() {
  std::lock_guard<std::mutex> lock(rig_mutex_);
  return {{"units", "mm"}, {"file", calibration_source_}, {"cameras", CamerasJson(rig_)}};
}

nlohmann::json HubService::Blobs() {
  std::future<BlobsSnapshot> answer = OnLoop([this] { return waiters_.ForBlobs(RealtimeNowNs(), masks_); });
  const BlobsSnapshot snapshot = Await(std::move(answer), kBlobsWaitSeconds + 1.0);
  std::lock_guard<std::mutex> lock(rig_mutex_);
  return BlobsJson(rig_, snapshot);
}

// ---- live wanding ----

void HubService::FinishWanding(const std::string& reason, bool solve) {
  const uint64_t now = RealtimeNowNs();
  // The capture ends first, so that a solve reads the whole session.
  if (wanding_.collecting() && captures_.running() && captures_.name() == wanding_.options().session) {
    const nlohmann::json summary = captures_.Stop(ingest_.stats(), now);
    log::Info("wanding {}: {}; {} frame sets captured", wanding_.options().session, reason,
              summary.value("frame_sets", 0));
  }
  wanding_.Stop(reason, now, solve, captures_.dir(), rig_);
}

nlohmann::json HubService::StartWanding(const WandingOptions& requested) {
  return OnLoop([this, requested] {
    wanding_.CheckCanStart();
    if (requested.intrinsics) {
      if (!SameCameras(*requested.intrinsics, rig_))
        throw ApiError(400, "'intrinsics' must hold the same cameras as the calibration serve runs with");
    }
    const uint64_t now = RealtimeNowNs();
    auto collection = std::make_unique<WandCollection>(rig_, requested, now);  // checks the options
    captures_.Start(requested.session, ingest_.stats(), now);
    wanding_.Start(std::move(collection));
    log::Info("wanding {} started ({}): {:.1f} mm {}, {} samples and {:.0f} % coverage per camera, timeout {:.0f} s",
              requested.session, requested.mode, requested.wand_length_mm,
              requested.SingleMarker() ? "scale bar" : "wand", requested.min_samples,
              100.0 * requested.coverage_target, requested.timeout_s);
    return wanding_.Json(RealtimeNowNs());
  });
}

nlohmann::json HubService::Wanding() {
  return OnLoop([this] {
    wanding_.Poll();
    return wanding_.Json(RealtimeNowNs());
  });
}

nlohmann::json HubService::StopWanding(bool solve) {
  return OnLoop([this, solve] {
    FinishWanding(solve ? "stopped on request" : "cancelled on request", solve);
    return wanding_.Json(RealtimeNowNs());
  });
}

nlohmann::json HubService::SolveWanding(const std::string& refine_intrinsics) {
  return OnLoop([this, refine_intrinsics] {
    wanding_.SolveAgain(refine_intrinsics, captures_.dir(), rig_);
    return wanding_.Json(RealtimeNowNs());
  });
}

nlohmann::json HubService::ApplyWandCalibration(bool save) {
  return OnLoop([this, save] {
    wanding_.Poll();
    const WandSolveOutcome& o = wanding_.Solved();
    if (!SameCameras(o.rig, rig_)) {
      std::string refused;
      for (const auto& c : o.report["cameras"])
        if (!c.value("accepted", false))
          refused += (refused.empty() ? "" : "; ") + std::string("camera ") + std::to_string(c.value("id", 0)) + ": " +
                     c.value("reason", "");
      throw ApiError(409, "not every camera was accepted, so the calibration is not applied (" + refused + ")");
    }
    std::string source = o.calibration_file;
    if (save) {
      ReplaceCalibrationKeepingOld(options_.calibration, o.calibration, RealtimeNowNs());
      source = options_.calibration;
    }
    UseRig(o.rig, source);
    wanding_.Applied(save ? options_.calibration : "");
    log::Info("calibration of wanding {} applied to the live reconstruction{}", wanding_.options().session,
              save ? " and saved to " + options_.calibration : "");
    return wanding_.Json(RealtimeNowNs());
  });
}

nlohmann::json HubService::ApplyMonitorSolve(uint32_t camera_id, bool save) {
  return OnLoop([this, camera_id, save] {
    if (!calibration_monitor_) throw ApiError(409, "the calibration monitor is off (serve --no-calibration-monitor)");
    calibration_monitor_->Finish();
    size_t index = rig_.cameras.size();
    for (size_t c = 0; c < rig_.cameras.size(); ++c) {
      if (rig_.cameras[c].id == camera_id) index = c;
    }
    if (index == rig_.cameras.size()) throw ApiError(404, "no camera " + std::to_string(camera_id) + " in the calibration");
    if (!calibration_monitor_->solved_pose(index))
      throw ApiError(409, "camera " + std::to_string(camera_id) +
                              " has no accepted solve to apply (see calibration_monitor in /api/status: it is solved "
                              "when it is bumped or drifting and the subject is in its view)");
    const Camera pose = *calibration_monitor_->solved_pose(index);
    Rig rig = rig_;
    rig.cameras[index] = pose;
    // The document written keeps every other field of the calibration serve runs with.
    nlohmann::json document;
    try {
      document = WithCameraPose(ReadJsonFile(calibration_source_), pose);
    } catch (const std::exception&) {
      document = RigToJson(rig);  // the source is gone or unreadable: the rig itself
    }
    std::string source = calibration_source_;
    if (save) {
      ReplaceCalibrationKeepingOld(options_.calibration, document, RealtimeNowNs());
      source = options_.calibration;
    }
    UseRig(rig, source);
    log::Info("calibration monitor: camera {}'s solved pose applied to the live reconstruction{}", camera_id,
              save ? " and saved to " + options_.calibration : "");
    return calibration_monitor_->StatusJson();
  });
}

nlohmann::json HubService::SetWorldFrame(const WorldFrameRequest& request) {
  request.Check();
  const double collect_s = request.frames / options_.rate_hz + 2.0;
  std::future<std::vector<FrameSet>> window = OnLoop([this, count = static_cast<size_t>(request.frames), collect_s] {
    if (wanding_.collecting()) throw ApiError(409, "a wanding is collecting; stop it before the floor step");
    return waiters_.ForFrameSets(count, RealtimeNowNs() + Ns(collect_s));
  });
  const std::vector<FrameSet> frames = Await(std::move(window), collect_s + options_.request_timeout_s + 1.0);
  if (frames.size() < 10) {
    throw ApiError(504, "only " + std::to_string(frames.size()) + " of " + std::to_string(request.frames) +
                            " frame sets arrived in " + std::to_string(static_cast<int>(collect_s)) +
                            " s (are the nodes running?)");
  }
  Rig rig;
  std::string source;
  {
    std::lock_guard<std::mutex> lock(rig_mutex_);
    rig = rig_;
    source = calibration_source_;
  }
  // The solve (a few dozen frame sets reconstructed) runs on the API's thread, not the loop's.
  const WorldFrameSolution solution = SolveWorldFrame(frames, rig, request);
  return OnLoop([this, solution, source] {
    if (source != calibration_source_)
      throw ApiError(409, "the calibration changed while the floor step ran (now " + calibration_source_ +
                              "); run it again");
    // The document written keeps every other field of the calibration serve runs with.
    nlohmann::json document;
    try {
      document = ReadJsonFile(calibration_source_);
      for (const Camera& camera : solution.rig.cameras) document = WithCameraPose(std::move(document), camera);
    } catch (const std::exception&) {
      document = RigToJson(solution.rig);  // the source is gone or unreadable: the rig itself
    }
    document["world_frame"] = {{"method", solution.report["method"]},
                               {"source", "serve (live)"},
                               {"frames_used", solution.report["frames_used"]},
                               {"fit_rms_mm", solution.report["fit_rms_mm"]},
                               {"up", solution.report["up"]}};
    ReplaceCalibrationKeepingOld(options_.calibration, document, RealtimeNowNs());
    UseRig(solution.rig, options_.calibration);
    nlohmann::json report = solution.report;
    report["saved"] = options_.calibration;
    log::Info("world frame set on the {} ({} of {} frame sets, fit {:.2f} mm): moved {:.1f} mm, turned {:.2f} deg, "
              "tilt removed {:.2f} deg; saved to {}",
              solution.report["method"].get<std::string>() == kWorldMethodFloor ? "floor" : "L-frame",
              solution.report["frames_used"].get<int>(), solution.report["frames"].get<size_t>(),
              solution.report["fit_rms_mm"].get<double>(), solution.report["moved_mm"].get<double>(),
              solution.report["turned_deg"].get<double>(), solution.report["tilt_removed_deg"].get<double>(),
              options_.calibration);
    return report;
  });
}

void HubService::UseRig(const Rig& rig, const std::string& source) {
  // The monitor judges residuals against the calibration it was made with: a new one starts
  // afresh (made again after the rig changes, so its worker never sees the change).
  const bool monitoring = calibration_monitor_ != nullptr;
  calibration_monitor_.reset();
  {
    std::lock_guard<std::mutex> lock(rig_mutex_);
    rig_ = rig;
    calibration_source_ = source;
  }
  live_ = MakeLive();
  if (monitoring)
    calibration_monitor_ = std::make_unique<CalibrationMonitor>(rig_, options_.rate_hz, CalibrationMonitorOptions());
  captures_.SetCalibrationFile(source);
}

}  // namespace mocap::service
