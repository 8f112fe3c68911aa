// Upright similarity transforms: a turn about the vertical (+z), a uniform scale and a
// translation, fitted in least squares to corresponding points. The labeller places a marker
// set's mean shape on a subject with them: people stand upright, so leaving out tilt keeps the
// fit from rolling a body over to match a raised arm; the scale takes another subject's size.
// Pure.
#pragma once

#include <vector>

#include <Eigen/Core>

namespace mocap {

struct UprightTransform {
  double yaw = 0.0;    // radians about +z
  double scale = 1.0;
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Vector3d Apply(const Eigen::Vector3d& p) const;
};

// target ~ transform(source). Needs at least 2 pairs (else the identity with the centroid
// shift). Without `with_scale` the scale is 1; with it, it is kept in [min_scale, max_scale].
UprightTransform FitUpright(const std::vector<Eigen::Vector3d>& source, const std::vector<Eigen::Vector3d>& target,
                            bool with_scale, double min_scale = 0.75, double max_scale = 1.35);

}  // namespace mocap
