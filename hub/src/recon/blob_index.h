// Per-camera index of one frame's observations sorted by normalized x, for "nearest blob to this
// image point within r" queries (prediction search, view completion) in O(log n + k).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "recon/frame_views.h"
#include "recon/matcher.h"

namespace mocap {

class BlobIndex {
 public:
  void Build(const RigModel& rig, const FrameViews& views);
  // Nearest observation of `camera` to `normalized` within `radius` (normalized units) that
  // `available` accepts, or -1.
  template <typename Accept>
  int Nearest(const FrameViews& views, int camera, const Eigen::Vector2d& normalized, double radius,
              Accept available) const;
  // Calls visit(observation, distance) for every observation of `camera` within `radius`.
  template <typename Visit>
  void ForEachWithin(const FrameViews& views, int camera, const Eigen::Vector2d& normalized, double radius,
                     Visit visit) const;

 private:
  std::vector<std::vector<int>> sorted_by_x_;
  std::vector<std::vector<double>> x_;  // the keys, contiguous for the binary search
};

template <typename Accept>
int BlobIndex::Nearest(const FrameViews& views, int camera, const Eigen::Vector2d& normalized,
                       double radius, Accept available) const {
  const std::vector<double>& xs = x_[camera];
  const std::vector<int>& sorted = sorted_by_x_[camera];
  size_t k = static_cast<size_t>(std::lower_bound(xs.begin(), xs.end(), normalized.x() - radius) - xs.begin());
  int best = -1;
  double best_distance = radius * radius;
  for (; k < xs.size() && xs[k] <= normalized.x() + radius; ++k) {
    const int index = sorted[k];
    const double d2 = (views.observations[index].normalized - normalized).squaredNorm();
    if (d2 <= best_distance && available(index)) {
      best_distance = d2;
      best = index;
    }
  }
  return best;
}

template <typename Visit>
void BlobIndex::ForEachWithin(const FrameViews& views, int camera, const Eigen::Vector2d& normalized,
                              double radius, Visit visit) const {
  const std::vector<double>& xs = x_[camera];
  const std::vector<int>& sorted = sorted_by_x_[camera];
  size_t k = static_cast<size_t>(std::lower_bound(xs.begin(), xs.end(), normalized.x() - radius) - xs.begin());
  for (; k < xs.size() && xs[k] <= normalized.x() + radius; ++k) {
    const double distance = (views.observations[sorted[k]].normalized - normalized).norm();
    if (distance <= radius) visit(sorted[k], distance);
  }
}

// Adds to the point every camera's available observation that lies within the triangulation's
// residual limit of its reprojection and is not yet a view, then re-solves. A marker partly
// gathered (prediction gates are small in some views) would otherwise leave blobs from which
// the matcher builds a duplicate.
void CompleteViews(const RigModel& rig, const FrameViews& views, const BlobIndex& index,
                   const UseCounts& used, const TriangulationOptions& options, TriangulatedPoint* point,
                   const std::vector<char>* shared = nullptr);

}  // namespace mocap
