// The interface every correspondence matcher implements, and the bookkeeping they share: which
// observations are already used by a point (a blob flagged merged may serve two markers).
#pragma once

#include <memory>
#include <vector>

#include "ingest/camera_frame.h"
#include "recon/frame_views.h"
#include "recon/recon_options.h"
#include "recon/triangulation.h"

namespace mocap {

// Use counts per observation, indexed like FrameViews::observations.
using UseCounts = std::vector<unsigned char>;

// True when the observation may still join a point: unused, or a merged blob used once. Inline:
// every gated blob search asks it.
inline bool IsAvailable(const Observation& observation, unsigned char use_count) {
  return use_count == 0 || ((observation.flags & kBlobMerged) != 0 && use_count < 2);
}

// Marks the point's observations used.
void MarkUsed(const TriangulatedPoint& point, UseCounts* used);

class Matcher {
 public:
  virtual ~Matcher() = default;
  // Finds markers among the available observations, appends their triangulated points and
  // marks the observations used.
  virtual void Match(const RigModel& rig, const FrameViews& views, UseCounts* used,
                     std::vector<TriangulatedPoint>* points) = 0;
};

// The matcher serves markers no track predicted: it requires min_views_without_prediction views.
std::unique_ptr<Matcher> CreateMatcher(const ReconstructorOptions& options);

// Shared final step of the clique-based matchers: takes candidate cliques in priority order and
// accepts each one's still-available members when they triangulate consistently.
void AcceptCliquesInOrder(const RigModel& rig, const FrameViews& views,
                          const std::vector<std::vector<int>>& cliques_in_order,
                          const TriangulationOptions& options, UseCounts* used,
                          std::vector<TriangulatedPoint>* points);

}  // namespace mocap
