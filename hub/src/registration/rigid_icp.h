// Rigid iterative closest point (seed 003, 3.1.1): pairs every source point with its nearest
// target point (a nanoflann k-d tree over the target), fits the rigid motion of the pairs with the
// project's Kabsch (geometry/rigid_fit.h) and repeats until the RMS stops falling. ICP finds the
// nearest local minimum only, so it starts from several guesses: the centroids matched and the
// principal axes of the two sets matched in each of their four proper sign combinations (and the
// identity rotation), keeping the best end. Given the target's normals (a mesh's), the best end is
// refined point-to-plane (each pair's distance along the target normal, Gauss-Newton on a small
// rotation and shift): points on a smooth surface pin it down where nearest vertices cannot, as
// a face's markers slide on its dome between vertices 2-3 mm apart.
// Errors: std::invalid_argument for bad options or fewer than 3 points in either set.
#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "geometry/rigid_fit.h"

namespace mocap {

struct RigidIcpOptions {
  int max_iterations = 100;       // per start, 1..10000
  double tolerance_mm = 1e-6;     // stop when the RMS falls by less than this
  // Pairs farther apart than this are left out of the fit (outliers, parts of the target the
  // source does not cover); 0 keeps every pair.
  double max_pair_distance_mm = 0.0;
  // Try the principal-axis starts as well as the identity one.
  bool principal_axis_starts = true;

  void Check() const;
};

struct RigidIcpResult {
  SimilarityTransform target_from_source;  // scale 1
  double rms_mm = 0.0;                     // over the pairs of the last fit
  size_t pairs = 0;                        // pairs within max_pair_distance_mm
  int iterations = 0;                      // of the start that won
};

// Nearest neighbours of a fixed point set (nanoflann's k-d tree behind a small interface).
class NearestPoints {
 public:
  explicit NearestPoints(const std::vector<Eigen::Vector3d>& points);
  ~NearestPoints();
  NearestPoints(const NearestPoints&) = delete;
  NearestPoints& operator=(const NearestPoints&) = delete;
  // Index of the point nearest to `query` and its squared distance.
  size_t Nearest(const Eigen::Vector3d& query, double* squared_distance) const;

 private:
  struct Index;
  Index* index_;
};

// target_normals: none, or one unit normal per target point (then the point-to-plane refinement
// runs and rms_mm is the RMS distance along the normals).
RigidIcpResult AlignRigidIcp(const std::vector<Eigen::Vector3d>& source, const std::vector<Eigen::Vector3d>& target,
                             const RigidIcpOptions& options,
                             const std::vector<Eigen::Vector3d>* target_normals = nullptr);

}  // namespace mocap
