// A recorded session's frame sets → its final marker rows: the chain `reconstruct` runs, written
// once here and tested without files. Each frame set is reconstructed with the tracker's
// predictions and tracked as it comes; hindsight undoes identity trades the next frames reveal
// and gives a new track that continues a lost marker its column (track/hindsight_swaps.h); the
// gap filler fills short gaps inside its bounded window (track/gap_filler.h); every finished row
// leaves through the sink in frame order, so memory does not grow with the session's length.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "geometry/camera.h"
#include "ingest/camera_frame.h"
#include "recon/reconstructor.h"
#include "track/gap_filler.h"
#include "track/hindsight_swaps.h"
#include "track/tracker.h"

namespace mocap::pipeline {

struct OfflineReconstructionOptions {
  ReconstructorOptions recon;
  TrackerOptions tracker;        // rate_hz is the session's (set by OfflineReconstruction)
  GapFillOptions gap_fill;       // max_spline_gap and window_frames follow from the two below
  HindsightSwapOptions hindsight;
  double max_spline_gap_s = 0.05;  // longest gap (seconds) filled by a spline
};

class OfflineReconstruction {
 public:
  using RowSink = GapFiller::Sink;

  // The rig must outlive this object. The session's rate sets the tracker's and, in frames, the
  // longest spline gap and the gap filler's window (that gap plus 2, at least a quarter second,
  // which also bounds the back-fill of a newly confirmed track). Throws std::invalid_argument on
  // bad options.
  OfflineReconstruction(const Rig& rig, double rate_hz, OfflineReconstructionOptions options, RowSink sink);

  // One frame set; a frame number not above the last one's is skipped (false).
  bool Add(const FrameSet& set);
  // The last added frame set's points, as reconstructed, before tracking decided anything.
  const std::vector<ReconstructedPoint>& points() const { return points_; }
  // Ends every track and flushes every held row to the sink; the number of output columns
  // (hindsight issues them when enabled, else the tracker). Call once, after at least one frame.
  int Finish();

  size_t frames() const { return frames_; }
  const Reconstructor& reconstructor() const { return reconstructor_; }
  const Tracker& tracker() const { return tracker_; }
  const HindsightSwaps& hindsight() const { return hindsight_; }
  const GapFiller& gap_filler() const { return filler_; }

 private:
  OfflineReconstructionOptions options_;
  Reconstructor reconstructor_;
  Tracker tracker_;
  GapFiller filler_;
  HindsightSwaps hindsight_;
  std::vector<ReconstructedPoint> points_;
  std::vector<TrackSample> samples_;
  size_t frames_ = 0;
  uint64_t last_frame_ = 0;
};

}  // namespace mocap::pipeline
