// The hub's in-memory form of what cameras saw: one camera's 2D blobs at one global frame number,
// and all cameras' blobs of one frame number assembled together. Produced by the ingest layer
// (live UDP or a session log), consumed by reconstruction, calibration and evaluation.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace mocap {

// Marker flag bits as on the wire (proto MarkerFlag).
enum BlobFlag : uint32_t {
  kBlobSaturated = 1,
  kBlobMerged = 2,
  kBlobBorder = 4,
};

struct Blob {
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();  // distorted image coordinates, px
  uint32_t area = 0;
  uint32_t peak = 0;
  uint32_t mean = 0;
  uint32_t flags = 0;
};

// Frame flag bit as on the wire (proto FRAME_FLAG_FREE_RUN): no trigger wire, the frame number
// is the slot of the capture time.
constexpr uint32_t kFrameFreeRun = 1;

struct CameraFrame {
  uint32_t camera_id = 0;
  uint64_t frame_number = 0;
  uint64_t trigger_time_ns = 0;
  uint64_t capture_time_ns = 0;
  uint64_t send_time_ns = 0;
  uint64_t receive_time_ns = 0;  // hub clock; 0 when unknown (simulated sessions)
  uint32_t width = 0;
  uint32_t height = 0;
  uint32_t flags = 0;            // proto FrameFlag bits
  std::vector<Blob> blobs;
};

// Every camera frame that arrived for one global frame number. Cameras that dropped the frame
// or missed the assembly deadline are simply absent.
struct FrameSet {
  uint64_t frame_number = 0;
  std::vector<CameraFrame> cameras;
};

}  // namespace mocap
