// Free-running cameras (no trigger wire: USB webcams) expose at their own instants, up to half a
// frame period from the frame set's; a marker moving 1 m/s is then up to 17 mm off at 30 Hz, in a
// different place in each camera. Before triangulation each camera's blobs are brought to the set's
// instant (epoch + frame number / rate): a blob continues its 2D track, the velocity taken from
// the same blob in the camera's previous frame, over the camera's offset from the set's instant.
// The same blob is the mutual nearest of the previous frame's blobs carried on by their own
// velocities: within a few pixels of that prediction where the velocity is known (neighbouring
// markers on a foot are as close in the image as one frame's step), within a step where not; a
// blob paired within a step only starts its track and moves once the prediction finds it again,
// so neighbours closer than a step that keep trading places stay as captured, never moved along
// each other's steps. The offset is the capture time stamp's, averaged over
// frames (a webcam's stamps jitter by about a millisecond; its phase drifts only by its rate
// error), and started again when it jumps (a drift across a slot boundary). A blob without a
// partner in the previous frame stays where it was.
#pragma once

#include <cstdint>
#include <map>
#include <vector>

#include <Eigen/Core>

#include "ingest/camera_frame.h"

namespace mocap {

struct BlobTimeAlignOptions {
  double rate_hz = 0.0;
  uint64_t epoch_ns = 0;         // the instant of frame 0
  double max_step_px = 40.0;     // the farthest a blob moves in one frame period
  double predicted_gate_px = 4.0;  // a tracked blob's distance from its prediction, at most
  double offset_weight = 0.05;   // a new stamp's weight in the averaged offset
  int max_gap_frames = 2;        // a previous frame further back gives no velocity

  // Throws std::invalid_argument naming the field, its value and the rule.
  void Check() const;
};

struct BlobTimeAlignStats {
  uint64_t blobs_moved = 0;  // continued along their tracks
  uint64_t blobs_kept = 0;   // left as captured: no confirmed track in the camera's previous frames
};

class BlobTimeAligner {
 public:
  explicit BlobTimeAligner(const BlobTimeAlignOptions& options);
  // Moves every camera's blobs in the set to the set's instant, in place.
  void Align(FrameSet* set);
  // The camera's averaged offset from the set's instants, s (0 before its first frame).
  double OffsetS(uint32_t camera_id) const;
  const BlobTimeAlignStats& stats() const { return stats_; }

 private:
  struct CameraTrack {
    uint64_t frame_number = 0;
    double offset_s = 0.0;
    std::vector<Eigen::Vector2d> pixels;  // as captured
    std::vector<Eigen::Vector2d> steps;   // px per frame; NaN where not known
  };
  void AlignCamera(uint64_t set_number, CameraFrame* frame);

  BlobTimeAlignOptions options_;
  double period_s_ = 0.0;
  std::map<uint32_t, CameraTrack> cameras_;
  BlobTimeAlignStats stats_;
};

}  // namespace mocap
