// Relaxation labelling over candidate cliques, then acceptance by final probability.
#include "recon/relaxation_matcher.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "util/counting_sort.h"

namespace mocap {

namespace {

// One label of one node: it is member `member` (numbered clique after clique) of its clique.
struct NodeLabel {
  int node = 0;
  int member = 0;
};

// The labels of every node that has any, grouped by node in increasing node order and, within a
// node, by clique: the order of the normalising sums. A counting sort on the node of labels made
// clique after clique. A frame's cliques touch a few dozen of its ~1000 observations (all of them
// in a dense set), so the iterations follow these lists rather than every node of the graph.
void GroupLabelsByNode(const std::vector<std::vector<int>>& cliques, size_t members, std::vector<NodeLabel>* labels,
                       std::vector<int>* node_begin) {
  thread_local std::vector<int> node_of_member, first_of_node;
  node_of_member.clear();
  int last_node = -1;
  for (const std::vector<int>& clique : cliques) {
    for (int node : clique) {
      node_of_member.push_back(node);
      last_node = std::max(last_node, node);
    }
  }
  labels->resize(members);
  CountingSort(
      static_cast<int>(members), last_node + 1, [&](int m) { return node_of_member[m]; }, &first_of_node,
      [&](int m, int slot) { (*labels)[slot] = {node_of_member[m], m}; });
  node_begin->clear();
  for (int node = 0; node <= last_node; ++node) {
    if (first_of_node[node + 1] > first_of_node[node]) node_begin->push_back(first_of_node[node]);
  }
  node_begin->push_back(static_cast<int>(members));
}

}  // namespace

RelaxationResult RelaxLabels(const EpipolarGraph& graph, const std::vector<std::vector<int>>& cliques,
                             double threshold_mm, const RelaxationOptions& options) {
  RelaxationResult result;
  const int num_cliques = static_cast<int>(cliques.size());
  // Edge strengths inside each clique, c_ij = 1 - d_ij / threshold (eq. 4); a tiny floor keeps
  // an edge right at the threshold from zeroing a whole clique's support. Clique k's size x size
  // block starts at strength_begin[k]; its members are numbered from member_begin[k] in the flat
  // per-member arrays (probabilities, supports). Per-thread scratch: the matcher runs every frame.
  thread_local std::vector<double> strength, probability, support;
  thread_local std::vector<size_t> strength_begin, member_begin;
  strength.clear();
  strength_begin.clear();
  member_begin.clear();
  size_t members = 0;
  for (int k = 0; k < num_cliques; ++k) {
    const std::vector<int>& clique = cliques[k];
    const size_t size = clique.size();
    strength_begin.push_back(strength.size());
    member_begin.push_back(members);
    members += size;
    strength.resize(strength.size() + size * size, 0.0);
    double* block = strength.data() + strength_begin.back();
    for (size_t a = 0; a < size; ++a) {
      for (size_t b = a + 1; b < size; ++b) {
        const double d = graph.EdgeDistance(clique[a], clique[b]);
        const double c = std::max(1e-3, 1.0 - d / threshold_mm);
        block[a * size + b] = c;
        block[b * size + a] = c;
      }
    }
  }
  member_begin.push_back(members);
  thread_local std::vector<NodeLabel> labels;
  thread_local std::vector<int> node_begin;
  GroupLabelsByNode(cliques, members, &labels, &node_begin);
  const size_t num_labelled = node_begin.size() - 1;
  // Initial weights 1/R_i (eq. 1).
  probability.resize(members);
  for (size_t n = 0; n < num_labelled; ++n) {
    const double count = static_cast<double>(node_begin[n + 1] - node_begin[n]);
    for (int i = node_begin[n]; i < node_begin[n + 1]; ++i) probability[labels[i].member] = 1.0 / count;
  }
  support.resize(members);
  for (int iteration = 0; iteration < options.max_iterations; ++iteration) {
    // Q(i, k) = sum_j c_ij P(j, k) over the other members j of clique k (eqs. 2-3).
    for (int k = 0; k < num_cliques; ++k) {
      const size_t size = member_begin[k + 1] - member_begin[k];
      const double* block = strength.data() + strength_begin[k];
      const double* clique_probability = probability.data() + member_begin[k];
      double* clique_support = support.data() + member_begin[k];
      // The block's diagonal is zero: a member's own term adds +0, which leaves the sum as the
      // sum over the others (no branch on b != a). Pairs, most cliques of a dense set, written out:
      // the same products.
      if (size == 2) {
        clique_support[0] = block[1] * clique_probability[1];
        clique_support[1] = block[2] * clique_probability[0];
        continue;
      }
      for (size_t a = 0; a < size; ++a) {
        double q = 0.0;
        for (size_t b = 0; b < size; ++b) q += block[a * size + b] * clique_probability[b];
        clique_support[a] = q;
      }
    }
    // P <- P Q / sum over the node's labels of P Q (eqs. 5-6).
    double max_change = 0.0;
    for (size_t n = 0; n < num_labelled; ++n) {
      const int begin = node_begin[n], end = node_begin[n + 1];
      if (end - begin < 2) continue;  // a single label keeps probability 1
      double normaliser = 0.0;
      for (int i = begin; i < end; ++i) {
        const int m = labels[i].member;
        normaliser += probability[m] * support[m];
      }
      if (normaliser <= 0.0) continue;
      for (int i = begin; i < end; ++i) {
        const int m = labels[i].member;
        const double updated = probability[m] * support[m] / normaliser;
        max_change = std::max(max_change, std::abs(updated - probability[m]));
        probability[m] = updated;
      }
    }
    result.iterations = iteration + 1;
    if (max_change < options.tolerance) break;
  }
  result.probability.resize(num_cliques);
  for (int k = 0; k < num_cliques; ++k) {
    result.probability[k].assign(probability.begin() + member_begin[k], probability.begin() + member_begin[k + 1]);
  }
  return result;
}

void RelaxationMatcher::Match(const RigModel& rig, const FrameViews& views, UseCounts* used,
                              std::vector<TriangulatedPoint>* points) {
  active_.resize(views.NumObservations());
  for (int i = 0; i < views.NumObservations(); ++i) {
    active_[i] = IsAvailable(views.observations[i], (*used)[i]) ? 1 : 0;
  }
  graph_.Build(rig, views, graph_options_, active_);
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
