// Greedy acceptance of triangulated candidate cliques by (views, reprojection error).
#include "recon/greedy_matcher.h"

#include <algorithm>

namespace mocap {

void GreedyMatcher::Match(const RigModel& rig, const FrameViews& views, UseCounts* used,
                          std::vector<TriangulatedPoint>* points) {
  std::vector<char> active(views.NumObservations());
  for (int i = 0; i < views.NumObservations(); ++i) {
    active[i] = IsAvailable(views.observations[i], (*used)[i]) ? 1 : 0;
  }
  graph_.Build(rig, views, graph_options_, active);
  const std::vector<std::vector<int>> cliques = graph_.CandidateCliques(rig, views);

  struct Scored {
    std::vector<int> kept;
    double rms_px;
  };
  std::vector<Scored> scored;
  TriangulatedPoint point;
  for (const std::vector<int>& clique : cliques) {
    if (TriangulateRobust(rig, views, clique, triangulation_options_, &point)) {
      scored.push_back({point.observations, point.rms_px});
    }
  }
  std::stable_sort(scored.begin(), scored.end(), [](const Scored& a, const Scored& b) {
    if (a.kept.size() != b.kept.size()) return a.kept.size() > b.kept.size();
    return a.rms_px < b.rms_px;
  });
  std::vector<std::vector<int>> ordered;
  ordered.reserve(scored.size());
  for (Scored& s : scored) ordered.push_back(std::move(s.kept));
  AcceptCliquesInOrder(rig, views, ordered, triangulation_options_, used, points);
}

}  // namespace mocap
