// A live recording for scripts (`record`): receives datagrams on its socket with serve's receive
// step (UdpSocket::Drain), hands each to the
// shared FrameIngest (validated, logged into the session as received, assembled into frame sets
// with a deadline) and each set to the caller (reconstruction, TRC streaming); announces the hub
// and stops on its limits. Bad input is counted per node, never fatal.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "ingest/frame_ingest.h"
#include "ingest/ingest_stats.h"
#include "ingest/session.h"
#include "ingest/udp_socket.h"

namespace mocap {

struct RecorderOptions {
  std::string listen = "0.0.0.0:30000";
  std::vector<uint32_t> cameras;      // node ids expected (from the calibration)
  ImageSizes image_sizes;             // the calibration's: frames of another size rescaled or refused
  double rate_hz = 240.0;
  uint64_t epoch_ns = 0;              // published to nodes in HubAnnounce
  std::string announce;               // broadcast HOST:PORT for HubAnnounce; empty = none
  double duration_s = 0.0;            // 0 = no time limit; datagrams the kernel received later are not recorded
  uint64_t max_frames = 0;            // frame sets; 0 = no limit
  double idle_timeout_s = 0.0;        // stop after this long without datagrams once data came; 0 = never
  FrameSetAssemblerOptions assembly;
  WireAuthOptions auth;               // keys directory, or the insecure development wire

  // Throws std::invalid_argument naming the first unusable setting (the hub's options policy).
  void Check() const;
};

class Recorder {
 public:
  explicit Recorder(RecorderOptions options);
  // Binds the socket (so tests can learn the port before nodes start); --duration counts from here.
  void Bind();
  uint16_t port() const { return socket_.port(); }
  // Receives until a limit is reached or *stop turns true; every set goes to on_set.
  void Run(SessionWriter* session, const std::function<void(const FrameSet&)>& on_set,
           const std::atomic<bool>* stop);
  const IngestStats& stats() const { return ingest_.stats(); }
  uint64_t frame_sets() const { return frame_sets_; }
  const FrameSetAssembler& assembler() const { return ingest_.assembler(); }
  const WireAuth& auth() const { return ingest_.auth(); }

 private:
  void Emit(std::vector<FrameSet> sets, const std::function<void(const FrameSet&)>& on_set);
  void Announce(uint64_t now_ns);

  RecorderOptions options_;
  UdpSocket socket_;
  std::optional<HostPort> announce_to_;
  FrameIngest ingest_;
  uint64_t frame_sets_ = 0;
  uint64_t next_announce_ns_ = 0;
  uint64_t bound_ns_ = 0;  // when Bind ran: the start of --duration
};

}  // namespace mocap
