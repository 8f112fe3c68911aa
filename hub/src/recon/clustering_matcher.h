// Baseline matcher after seed 000 (4.3): closest points of every ray pair from two cameras,
// grouped so that a group holds at most one ray per camera and every pair of its rays passes
// within the threshold (default 30 mm). Pairs join groups in order of increasing distance.
// Groups are triangulated like every other matcher's output, so the comparison is about the
// correspondences, not the point estimate.
#pragma once

#include "recon/matcher.h"

namespace mocap {

class ClusteringMatcher : public Matcher {
 public:
  ClusteringMatcher(const ClusteringOptions& options, double min_depth_mm,
                    const TriangulationOptions& triangulation_options)
      : options_(options), min_depth_mm_(min_depth_mm),
        triangulation_options_(triangulation_options) {}

  void Match(const RigModel& rig, const FrameViews& views, UseCounts* used,
             std::vector<TriangulatedPoint>* points) override;

 private:
  ClusteringOptions options_;
  double min_depth_mm_;
  TriangulationOptions triangulation_options_;
};

}  // namespace mocap
