// The last step of a frame's reconstruction: every point must be a marker of its own. Points are
// taken best first (more views, then earlier: predictions of the oldest tracks come first); a
// point is dropped when it lies closer to a kept point than two markers can (a duplicate), or,
// for a point no track predicted, when fewer than min_views of its views carry evidence of their
// own, i.e. lie farther than a view's residual limit from every kept point's reprojection (a ghost
// made of other markers' blobs; a merged blob serving two markers counts as explained). A tracked
// point is spared that test: two markers' images coincide in some views, and a fast marker seen
// by two cameras would lose frames to it. Dropped points give their blobs back.
// Single-threaded; reuses its buffers between frames; never throws on data.
#pragma once

#include <vector>

#include "recon/blob_index.h"
#include "recon/matcher.h"

namespace mocap {

class GhostFilter {
 public:
  GhostFilter(const GhostFilterOptions& options, const TriangulationOptions& triangulation)
      : options_(options), triangulation_(triangulation) {}
  // New gates (the rig's noise moved, recon/rig_noise.h).
  void SetTriangulationOptions(const TriangulationOptions& triangulation) { triangulation_ = triangulation; }

  // Sets (*keep)[i] for every point; the first `tracked` points came from track predictions.
  // Releases the views of the points dropped in *used. Returns how many were dropped.
  int Apply(const RigModel& rig, const FrameViews& views, const BlobIndex& index,
            const std::vector<TriangulatedPoint>& points, size_t tracked, UseCounts* used,
            std::vector<char>* keep);

 private:
  // Fills order_ with the points' indices, most views first, ties in index order.
  void OrderByViews(const std::vector<TriangulatedPoint>& points);
  void MarkExplained(const RigModel& rig, const FrameViews& views, const BlobIndex& index,
                     const TriangulatedPoint& point);

  GhostFilterOptions options_;
  TriangulationOptions triangulation_;
  std::vector<int> order_;
  std::vector<char> explained_;  // per observation: near a kept point's reprojection
  std::vector<int> by_views_begin_;  // OrderByViews' buckets
  std::vector<Eigen::Vector3d> kept_positions_;  // contiguous: every point is compared with them all
  std::vector<char> has_view_;  // per camera, of the point being marked
};

}  // namespace mocap
