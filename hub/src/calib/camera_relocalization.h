// A knocked camera found again from the subject alone. The cameras that did not move triangulate
// the capture's markers; the knocked camera's blobs are those markers seen from a pose that is
// unknown but near the old one. The pairing of points with blobs cannot come from the old pose
// (a 2 deg turn moves every marker by ~40 px, more than the distance between markers of a
// body), so it is found in stages that each need less of the old pose:
//   1. vote: every (point projected with the old pose, blob within search_px) pair of a frame
//      votes for its image shift; a knock shifts all of a camera's markers by nearly the same
//      amount, wrong pairs scatter, so the peak is the knock's shift;
//   2. candidates: each point's nearest blob around its shifted projection, kept when
//      unambiguous (ratio test) and no other point claims the blob;
//   3. PnP + RANSAC (OpenCV solvePnPRansac, AP3P on undistorted normalized coordinates) on the
//      candidates: the first pose that does not depend on the old one;
//   4. re-pairing with that pose under a narrowing gate, each round followed by a non-linear
//      resection (Ceres, Huber loss, intrinsics held).
// Pure function; options Check() throws std::invalid_argument; a camera that cannot be found
// again is a result with the reason and what to do, never an exception.
#pragma once

#include <cstddef>
#include <deque>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "calib/marker_residuals.h"
#include "geometry/camera.h"

namespace mocap {

struct CameraRelocalizationOptions {
  double search_px = 250.0;       // largest image shift a knock may cause (the vote's range)
  double vote_bin_px = 8.0;       // the vote's cell; the peak sums 3 x 3 cells
  size_t max_vote_frames = 400;   // frames that vote (spread evenly over the input)
  double match_px = 40.0;         // candidates are searched this far around the shifted projection
  double ambiguity_ratio = 1.5;   // second nearest blob at least this much further than the nearest
  double ransac_px = 3.0;         // PnP RANSAC inlier threshold
  int ransac_iterations = 2000;
  size_t max_candidates = 20000;  // candidates given to RANSAC (spread evenly)
  size_t min_inliers = 30;        // fewer agreeing correspondences: refused
  double min_inlier_fraction = 0.25;  // nor when fewer of the candidates agree (blobs that are not the markers)
  double loss_scale_px = 1.0;     // Huber scale of the resections
  double outlier_px = 1.5;        // final gate: max(this, 5 robust sigma)
  int max_iterations = 100;

  void Check() const;
};

struct CameraRelocalization {
  bool ok = false;
  Camera camera;                                       // the solved pose (intrinsics as given)
  Eigen::Vector2d shift_px = Eigen::Vector2d::Zero();  // the voted image shift
  size_t points = 0;                                   // points the unmoved cameras triangulate
  size_t candidates = 0;                               // correspondences given to RANSAC
  size_t ransac_inliers = 0;
  size_t inliers = 0;                                  // views within the final gate
  double gate_px = 0.0;                                // the final gate
  double median_px = 0.0;                              // median residual of the final views
  std::string reason;                                  // why not ok, and what to do
};

// Finds rig.cameras[camera] again. `excluded` (rig order) marks the cameras whose views must
// not triangulate the points (the moved ones, this one included). `blobs` gives the frames'
// blobs (frame order; frames without an entry are skipped).
CameraRelocalization RelocalizeCamera(const Rig& rig, size_t camera, const std::vector<char>& excluded,
                                      const std::deque<MarkerSample>& samples, const std::deque<FrameBlobs>& blobs,
                                      const CameraRelocalizationOptions& options);

// The blob of `blobs` nearest to `predicted` when it is within `gate_px` and the second
// nearest is at least `ambiguity_ratio` times further; -1 otherwise.
int UnambiguousNearestBlob(const std::vector<Eigen::Vector2d>& blobs, const Eigen::Vector2d& predicted,
                           double gate_px, double ambiguity_ratio);

}  // namespace mocap
