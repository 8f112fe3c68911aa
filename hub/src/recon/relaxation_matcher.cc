// Relaxation labelling over candidate cliques, then acceptance by final probability.
#include "recon/relaxation_matcher.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace mocap {

RelaxationResult RelaxLabels(const EpipolarGraph& graph, const std::vector<std::vector<int>>& cliques,
                             double threshold_mm, const RelaxationOptions& options) {
  RelaxationResult result;
  const int num_cliques = static_cast<int>(cliques.size());
  // Labels of each node as (clique, slot) pairs.
  std::vector<std::vector<std::pair<int, int>>> labels_of_node(graph.NumNodes());
  for (int k = 0; k < num_cliques; ++k) {
    for (int m = 0; m < static_cast<int>(cliques[k].size()); ++m) {
      labels_of_node[cliques[k][m]].emplace_back(k, m);
    }
  }
  // Edge strengths inside each clique, c_ij = 1 - d_ij / threshold (eq. 4); a tiny floor keeps
  // an edge right at the threshold from zeroing a whole clique's support.
  std::vector<std::vector<double>> strength(num_cliques);
  for (int k = 0; k < num_cliques; ++k) {
    const std::vector<int>& clique = cliques[k];
    const size_t size = clique.size();
    strength[k].assign(size * size, 0.0);
    for (size_t a = 0; a < size; ++a) {
      for (size_t b = a + 1; b < size; ++b) {
        const double d = graph.EdgeDistance(clique[a], clique[b]);
        const double c = std::max(1e-3, 1.0 - d / threshold_mm);
        strength[k][a * size + b] = c;
        strength[k][b * size + a] = c;
      }
    }
  }
  // Initial weights 1/R_i (eq. 1).
  result.probability.resize(num_cliques);
  for (int k = 0; k < num_cliques; ++k) {
    result.probability[k].resize(cliques[k].size());
    for (size_t m = 0; m < cliques[k].size(); ++m) {
      result.probability[k][m] = 1.0 / labels_of_node[cliques[k][m]].size();
    }
  }
  std::vector<std::vector<double>> support(num_cliques);
  for (int iteration = 0; iteration < options.max_iterations; ++iteration) {
    // Q(i, k) = sum_j c_ij P(j, k) over the other members j of clique k (eqs. 2-3).
    for (int k = 0; k < num_cliques; ++k) {
      const size_t size = cliques[k].size();
      support[k].assign(size, 0.0);
      for (size_t a = 0; a < size; ++a) {
        double q = 0.0;
        for (size_t b = 0; b < size; ++b) {
          if (b != a) q += strength[k][a * size + b] * result.probability[k][b];
        }
        support[k][a] = q;
      }
    }
    // P <- P Q / sum over the node's labels of P Q (eqs. 5-6).
    double max_change = 0.0;
    for (const auto& labels : labels_of_node) {
      if (labels.size() < 2) continue;  // a single label keeps probability 1
      double normaliser = 0.0;
      for (const auto& [k, m] : labels) normaliser += result.probability[k][m] * support[k][m];
      if (normaliser <= 0.0) continue;
      for (const auto& [k, m] : labels) {
        const double updated = result.probability[k][m] * support[k][m] / normaliser;
        max_change = std::max(max_change, std::abs(updated - result.probability[k][m]));
        result.probability[k][m] = updated;
      }
    }
    result.iterations = iteration + 1;
    if (max_change < options.tolerance) break;
  }
  return result;
}

void RelaxationMatcher::Match(const RigModel& rig, const FrameViews& views, UseCounts* used,
                              std::vector<TriangulatedPoint>* points) {
  std::vector<char> active(views.NumObservations());
  for (int i = 0; i < views.NumObservations(); ++i) {
    active[i] = IsAvailable(views.observations[i], (*used)[i]) ? 1 : 0;
  }
  graph_.Build(rig, views, graph_options_, active);
  const std::vector<std::vector<int>> cliques = graph_.CandidateCliques(rig, views);
  if (cliques.empty()) return;
  const RelaxationResult relaxed =
      RelaxLabels(graph_, cliques, graph_options_.max_ray_distance_mm, relaxation_options_);

  // A clique is as credible as its least convinced member; larger cliques break ties.
  std::vector<double> credibility(cliques.size());
  for (size_t k = 0; k < cliques.size(); ++k) {
    credibility[k] = *std::min_element(relaxed.probability[k].begin(), relaxed.probability[k].end());
  }
  std::vector<int> order(cliques.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    if (credibility[a] != credibility[b]) return credibility[a] > credibility[b];
    return cliques[a].size() > cliques[b].size();
  });
  std::vector<std::vector<int>> ordered;
  ordered.reserve(order.size());
  for (int k : order) ordered.push_back(cliques[k]);
  AcceptCliquesInOrder(rig, views, ordered, triangulation_options_, used, points);
}

}  // namespace mocap
