// Live recording loop (see recorder.h).
#include "ingest/recorder.h"

#include <algorithm>
#include <stdexcept>

#include "wire/packet.h"

namespace mocap {

void RecorderOptions::Check() const {
  if (cameras.empty()) throw std::invalid_argument("no cameras: the calibration names none");
  if (!(rate_hz > 0.0 && rate_hz <= 2000.0)) throw std::invalid_argument("rate must be within (0, 2000] Hz");
  if (duration_s < 0.0) throw std::invalid_argument("duration must not be negative");
  ParseHostPort(listen);  // throws std::invalid_argument naming the bad address
  if (!announce.empty()) ParseHostPort(announce);
  assembly.Check();
  auth.Check();
}

Recorder::Recorder(RecorderOptions options)
    : options_((options.Check(), std::move(options))), ingest_(options_.cameras, options_.assembly, options_.auth, options_.image_sizes) {}

void Recorder::Bind() {
  socket_.Bind(ParseHostPort(options_.listen));
  bound_ns_ = RealtimeNowNs();  // --duration counts from here: datagrams queue from now on
  if (!options_.announce.empty()) {
    announce_to_ = ParseHostPort(options_.announce);
    socket_.EnableBroadcast();
  }
}

void Recorder::Announce(uint64_t now_ns) {
  if (!announce_to_ || now_ns < next_announce_ns_) return;
  next_announce_ns_ = now_ns + 1'000'000'000ull;
  // One announce per node with a key, each sealed for its node (a broadcast reaches them all).
  const std::vector<uint8_t> packet = wire::EncodeHubAnnounce(port(), options_.epoch_ns, options_.rate_hz);
  for (const auto& datagram : ingest_.auth().SealForEveryNode(packet, now_ns)) socket_.SendTo(*announce_to_, datagram);
}

void Recorder::Emit(std::vector<FrameSet> sets, const std::function<void(const FrameSet&)>& on_set) {
  for (FrameSet& set : sets) {
    if (options_.max_frames && frame_sets_ >= options_.max_frames) return;
    ++frame_sets_;
    if (on_set) on_set(set);
  }
}

void Recorder::Run(SessionWriter* session, const std::function<void(const FrameSet&)>& on_set,
                   const std::atomic<bool>* stop) {
  const uint64_t start = bound_ns_ ? bound_ns_ : RealtimeNowNs();
  const uint64_t end = options_.duration_s > 0 ? start + uint64_t(options_.duration_s * 1e9) : 0;
  uint64_t last_datagram = 0, last_flush = start;
  while (!(stop && stop->load())) {
    const uint64_t now = RealtimeNowNs();
    if (end && now >= end) break;
    if (options_.max_frames && frame_sets_ >= options_.max_frames) break;
    if (options_.idle_timeout_s > 0 && last_datagram &&
        now > last_datagram + uint64_t(options_.idle_timeout_s * 1e9))
      break;
    Announce(now);
    ingest_.auth().ReloadIfChanged(now);
    // serve's receive step (UdpSocket::Drain): a first datagram waited for briefly, then what is
    // queued, bounded; then what is complete or overdue is handed out.
    uint64_t last_receive = 0;
    bool past_end = false;
    const size_t drained = socket_.Drain(1, UdpSocket::kDrainMax, [&](const Datagram& d) {
      // --duration holds to the kernel's receive time: what came after the end (while this turn
      // ran late on a busy machine) is not recorded.
      if (end && d.receive_time_ns >= end) past_end = true;
      if (past_end) return;
      last_datagram = RealtimeNowNs();
      last_receive = std::max(last_receive, d.receive_time_ns);
      ingest_.Add(d, session);
    });
    const uint64_t after = RealtimeNowNs();
    // Deadlines on the receive clock while datagrams are still queued (as serve's loop).
    Emit(ingest_.Collect(drained == UdpSocket::kDrainMax ? last_receive : after), on_set);
    if (past_end) break;
    // Raw log: flushed at least every 50 ms so a crash loses little.
    if (after > last_flush + 50'000'000ull) {
      session->Flush();
      last_flush = after;
    }
  }
  Emit(ingest_.Flush(), on_set);
  session->Flush();
}

}  // namespace mocap
