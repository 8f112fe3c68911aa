// Ghost removal by probabilistic relaxation labelling (seed 001 section 2.2). Objects are the
// observations, the labels of an observation are the candidate cliques containing it. Weights
// start at 1/R; a label's support is the sum over its other members j of c_ij * P(j, label),
// with edge strength c_ij = 1 - d_ij / threshold; P <- P * Q / normalisation until it settles.
// Cliques are then accepted in order of their weakest member's final probability.
#pragma once

#include <vector>

#include "recon/epipolar_graph.h"
#include "recon/matcher.h"

namespace mocap {

// The labelling itself, separate from the matcher so tests can inspect probabilities.
struct RelaxationResult {
  // probability[k][m]: P(member m of clique k takes label k).
  std::vector<std::vector<double>> probability;
  int iterations = 0;
};

RelaxationResult RelaxLabels(const EpipolarGraph& graph, const std::vector<std::vector<int>>& cliques,
                             double threshold_mm, const RelaxationOptions& options);

class RelaxationMatcher : public Matcher {
 public:
  RelaxationMatcher(const EpipolarGraphOptions& graph_options,
                    const RelaxationOptions& relaxation_options,
                    const TriangulationOptions& triangulation_options)
      : graph_options_(graph_options),
        relaxation_options_(relaxation_options),
        triangulation_options_(triangulation_options) {}

  void Match(const RigModel& rig, const FrameViews& views, UseCounts* used,
             std::vector<TriangulatedPoint>* points) override;

 private:
  EpipolarGraphOptions graph_options_;
  RelaxationOptions relaxation_options_;
  TriangulationOptions triangulation_options_;
  EpipolarGraph graph_;
  std::vector<char> active_;  // per observation, available to this match: kept between frames
};

}  // namespace mocap
