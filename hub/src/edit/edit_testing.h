// Synthetic takes for the edit tests: four markers on one rigid segment that turns and travels
// smoothly (a corner and three others, 80-150 mm apart), sampled at 100 Hz from frame 1000.
#pragma once

#include <cmath>

#include <Eigen/Geometry>

#include "edit/edited_take.h"

namespace mocap::edit::testing {

inline Eigen::Vector3d SegmentPoint(size_t marker, double t) {
  static const Eigen::Vector3d kLocal[4] = {{0, 0, 0}, {120, 0, 0}, {0, 150, 0}, {40, 50, 80}};
  const Eigen::Matrix3d r = (Eigen::AngleAxisd(0.9 * std::sin(1.3 * t), Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(0.5 * std::sin(0.7 * t + 0.4), Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  const Eigen::Vector3d travel(400.0 * std::sin(0.8 * t), 250.0 * std::cos(0.5 * t), 900.0 + 60.0 * std::sin(2.1 * t));
  return travel + r * kLocal[marker % 4];
}

inline EditedTake SegmentTake(size_t frames) {
  MarkerTrajectories m;
  m.rate_hz = 100.0;
  m.names = {"A", "B", "C", "D"};
  for (size_t f = 0; f < frames; ++f) {
    const size_t i = m.AddFrame(1000 + f);
    for (size_t c = 0; c < 4; ++c) m.At(i, c) = SegmentPoint(c, static_cast<double>(f) / m.rate_hz);
  }
  return EditedTake::FromMeasured(std::move(m));
}

}  // namespace mocap::edit::testing
