// What `serve` is started with (its command line and hub.conf), checked as a whole, and the
// options of each object the service owns, derived from it in one place.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "bodies/body_live_filter.h"
#include "geometry/camera.h"
#include "ingest/frame_set_assembler.h"
#include "ingest/session.h"
#include "ingest/wire_auth.h"
#include "recon/recon_options.h"
#include "service/capture.h"
#include "service/control_requests.h"
#include "service/node_registry.h"
#include "track/track_options.h"

namespace mocap::service {

struct ServeOptions {
  std::string listen = "0.0.0.0:30000";   // UDP from the nodes
  std::string calibration;                // calibration JSON: the cameras and their geometry
  std::string sessions_dir = "sessions";  // captures go to sessions_dir/NAME; "": none (record's hub)
  std::string masks_file;                 // the installation's masks (JSON); empty: none kept
  std::string bodies_file;                // rigid bodies (bodies/body_definition.h); empty: none
  BodyLiveFilterOptions body_filter;      // their orientations refined from past frames
  std::string labels_file;                // marker set (labels/marker_set.h); empty: unnamed points
  // A calibrated subject (skeleton/skeleton.h) solved on every frame's named points (needs
  // labels_file): pipeline/live_skeleton.h. Empty: none.
  std::string skeleton_file;
  std::string skeleton_up = "z";          // the calibration's up axis: x, y, z, -x, -y or -z
  double rate_hz = 240.0;
  uint64_t epoch_ns = 0;                  // time of frame 0; 0 = the service's start
  std::string announce;                   // broadcast HOST:PORT for HubAnnounce; empty = none
  double deadline_ms = 20.0;              // a frame set waits this long for late cameras
  // While a frame set is arriving, the loop polls the socket without sleeping for up to this long
  // after each datagram (0: it sleeps at once). A sleeping thread, and a virtual CPU gone idle,
  // take tens to hundreds of microseconds to wake; spinning through the few milliseconds a set's
  // datagrams take to arrive saves that on its last one, for a core busy meanwhile.
  double busy_poll_us = 0.0;
  // The frame loop under SCHED_FIFO at this priority (1-99; 0: the ordinary policy): no ordinary
  // thread of any process on its core delays a frame set. Needs root, CAP_SYS_NICE or an
  // RLIMIT_RTPRIO (the systemd unit's LimitRTPRIO=); refused, serve warns and runs on.
  int realtime_priority = 0;
  bool free_run = false;
  double node_lost_after_s = 3.0;
  double request_timeout_s = 2.0;         // a node that does not answer a control this long
  int auto_mask_max_frames = 1000;
  ReconstructorOptions recon;             // as `reconstruct` takes them
  TrackerOptions tracker;                 // likewise; its rate is rate_hz
  bool calibration_monitor = true;        // watch the cameras' residuals (calibration_monitor.h)
  WireAuthOptions auth;                   // the nodes' keys, or the insecure development wire
  CaptureDiskOptions disk;                // the sessions disk's free space (capture.h)
  // mocap-hub itself, run as `process` for the processing jobs (processing_jobs.h); empty: none.
  std::string processing_executable;

  // Throws std::invalid_argument naming the bad option.
  void Check() const;
};

// "x", "y", "z", "-x", "-y", "-z" -> LiveSkeletonOptions::up_axis (0, 1, 2, -1, -2, -3); throws
// std::invalid_argument for anything else.
int SkeletonUpAxis(const std::string& text);

// The calibration serve runs with; throws std::invalid_argument without one or with fewer than
// two cameras (std::runtime_error from the reader for a file it refuses).
Rig LoadServeRig(const std::string& path);
// The time of frame 0: the options' epoch, else now (wall clock).
uint64_t EpochOf(const ServeOptions& options);
FrameSetAssemblerOptions AssemblyOf(const ServeOptions& options, uint64_t epoch_ns);
// Only the calibration's cameras are nodes of this installation.
NodeRegistryOptions RegistryOf(const ServeOptions& options, const Rig& rig);
ControlRequestsOptions ControlsOf(const ServeOptions& options, uint64_t now_ns);
// What every capture's session.json starts from.
SessionInfo SessionBase(const ServeOptions& options, const Rig& rig, uint64_t epoch_ns);
std::vector<uint32_t> CameraIds(const Rig& rig);
// The same camera ids (in any order).
bool SameCameras(const Rig& a, const Rig& b);

}  // namespace mocap::service
