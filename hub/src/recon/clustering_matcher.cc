// Ray-pair clustering: sorted pairs, groups grown under the one-ray-per-camera rule.
#include "recon/clustering_matcher.h"

#include <algorithm>

#include "recon/epipolar_graph.h"

namespace mocap {

void ClusteringMatcher::Match(const RigModel& rig, const FrameViews& views, UseCounts* used,
                              std::vector<TriangulatedPoint>* points) {
  const int n = views.NumObservations();
  struct Pair {
    double distance;
    int a, b;
  };
  std::vector<Pair> pairs;
  RayPair ray_pair;
  const auto rays_meet = [&](int a, int b, RayPair* out) {
    const Observation& oa = views.observations[a];
    const Observation& ob = views.observations[b];
    return ClosestPointsOfRays(rig.camera(oa.camera).center_in_world, oa.ray_in_world,
                               rig.camera(ob.camera).center_in_world, ob.ray_in_world, out) &&
           out->distance <= options_.max_ray_distance_mm && out->depth_a >= min_depth_mm_ &&
           out->depth_b >= min_depth_mm_;
  };
  for (int a = 0; a < n; ++a) {
    if (!IsAvailable(views.observations[a], (*used)[a])) continue;
    for (int b = views.camera_begin[views.observations[a].camera + 1]; b < n; ++b) {
      if (!IsAvailable(views.observations[b], (*used)[b])) continue;
      if (rays_meet(a, b, &ray_pair)) pairs.push_back({ray_pair.distance, a, b});
    }
  }
  std::sort(pairs.begin(), pairs.end(),
            [](const Pair& x, const Pair& y) { return x.distance < y.distance; });

  std::vector<int> group_of(n, -1);
  std::vector<std::vector<int>> groups;
  // A ray may join a group when the group has no ray of its camera and all rays meet it.
  const auto can_join = [&](int ray, const std::vector<int>& group) {
    for (int member : group) {
      if (views.observations[member].camera == views.observations[ray].camera) return false;
      if (!rays_meet(ray, member, &ray_pair)) return false;
    }
    return true;
  };
  for (const Pair& pair : pairs) {
    const int ga = group_of[pair.a];
    const int gb = group_of[pair.b];
    if (ga < 0 && gb < 0) {
      group_of[pair.a] = group_of[pair.b] = static_cast<int>(groups.size());
      groups.push_back({pair.a, pair.b});
    } else if (ga >= 0 && gb < 0) {
      if (can_join(pair.b, groups[ga])) {
        groups[ga].push_back(pair.b);
        group_of[pair.b] = ga;
      }
    } else if (gb >= 0 && ga < 0) {
      if (can_join(pair.a, groups[gb])) {
        groups[gb].push_back(pair.a);
        group_of[pair.a] = gb;
      }
    }
  }
  // Larger groups first so that a shared merged blob goes to the better-supported marker.
  std::stable_sort(groups.begin(), groups.end(),
                   [](const std::vector<int>& x, const std::vector<int>& y) {
                     return x.size() > y.size();
                   });
  AcceptCliquesInOrder(rig, views, groups, triangulation_options_, used, points);
}

}  // namespace mocap
