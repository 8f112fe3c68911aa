// Baseline matcher: every candidate clique of the epipolar graph is triangulated, then cliques
// are accepted greedily, most views first and lowest reprojection error next.
#pragma once

#include "recon/epipolar_graph.h"
#include "recon/matcher.h"

namespace mocap {

class GreedyMatcher : public Matcher {
 public:
  GreedyMatcher(const EpipolarGraphOptions& graph_options,
                const TriangulationOptions& triangulation_options)
      : graph_options_(graph_options), triangulation_options_(triangulation_options) {}

  void Match(const RigModel& rig, const FrameViews& views, UseCounts* used,
             std::vector<TriangulatedPoint>* points) override;

 private:
  EpipolarGraphOptions graph_options_;
  TriangulationOptions triangulation_options_;
  EpipolarGraph graph_;
};

}  // namespace mocap
