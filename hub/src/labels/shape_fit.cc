// Upright similarity fit (see shape_fit.h): the yaw has a closed form on the centred horizontal
// components; the scale follows from the turned source.
#include "labels/shape_fit.h"

#include <algorithm>
#include <cmath>

namespace mocap {

Eigen::Vector3d UprightTransform::Apply(const Eigen::Vector3d& p) const {
  const double c = std::cos(yaw), s = std::sin(yaw);
  return scale * Eigen::Vector3d(c * p.x() - s * p.y(), s * p.x() + c * p.y(), p.z()) + translation;
}

UprightTransform FitUpright(const std::vector<Eigen::Vector3d>& source, const std::vector<Eigen::Vector3d>& target,
                            bool with_scale, double min_scale, double max_scale) {
  UprightTransform fit;
  const size_t n = std::min(source.size(), target.size());
  if (n == 0) return fit;
  Eigen::Vector3d cs = Eigen::Vector3d::Zero(), ct = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < n; ++i) cs += source[i], ct += target[i];
  cs /= static_cast<double>(n), ct /= static_cast<double>(n);
  double dot = 0.0, cross = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d a = source[i] - cs, b = target[i] - ct;
    dot += a.x() * b.x() + a.y() * b.y();
    cross += a.x() * b.y() - a.y() * b.x();
  }
  fit.yaw = n >= 2 && (dot != 0.0 || cross != 0.0) ? std::atan2(cross, dot) : 0.0;
  if (with_scale && n >= 2) {
    UprightTransform turn = fit;
    double num = 0.0, den = 0.0;
    for (size_t i = 0; i < n; ++i) {
      const Eigen::Vector3d a = turn.Apply(source[i] - cs), b = target[i] - ct;
      num += a.dot(b), den += a.squaredNorm();
    }
    fit.scale = den > 0.0 ? std::clamp(num / den, min_scale, max_scale) : 1.0;
  }
  fit.translation = ct - fit.Apply(cs);  // translation is zero here, so Apply turns and scales
  return fit;
}

}  // namespace mocap
