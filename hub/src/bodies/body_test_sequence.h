// Test helpers shared by the orientation estimators' tests (offline body_smoothing_test.cc, live
// body_live_filter_test.cc): a body's markers along a known rotation with Gaussian noise, each
// frame fitted alone, and the error measures. Test code only.
#pragma once

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Geometry>

#include "bodies/body_rotation_window.h"
#include "bodies/body_tracker.h"
#include "geometry/rigid_fit.h"

namespace mocap::body_test {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

inline RigidBodyDefinition Wand() {
  RigidBodyDefinition body;
  body.name = "wand";
  body.markers = {{0, 0, 0}, {110, 0, 0}, {30, 75, 0}, {45, 20, 60}};
  body.pivot = {10, -5, 3};
  return body;
}

struct Sequence {
  std::vector<Eigen::Matrix3d> truth;
  std::vector<BodyFrameMarkers> markers;
  std::vector<BodyPose> poses;  // per-frame least-squares fits
};

// A body turning by `rotation_of(f)` at frame f, its markers' points with Gaussian noise of
// `noise_mm` per axis, each frame fitted alone.
template <typename RotationOf>
Sequence Simulate(const RigidBodyDefinition& body, int frames, double noise_mm, RotationOf rotation_of,
                  uint64_t seed = 7) {
  std::mt19937_64 random(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  Sequence s;
  for (int f = 0; f < frames; ++f) {
    const Eigen::Matrix3d r = rotation_of(f);
    const Eigen::Vector3d t(100.0 + 8.0 * f, -50.0, 1200.0 + 3.0 * f);
    BodyFrameMarkers m;
    for (const Eigen::Vector3d& b : body.markers) {
      m.in_body.push_back(b);
      m.in_world.push_back(r * b + t + noise_mm * Eigen::Vector3d(gauss(random), gauss(random), gauss(random)));
    }
    const SimilarityTransform fit = FitRigid(m.in_body, m.in_world);
    BodyPose pose;
    pose.tracked = true;
    pose.orientation = Eigen::Quaterniond(fit.rotation);
    pose.position = fit.translation;
    pose.pivot = fit.rotation * body.pivot + fit.translation;
    pose.markers = body.markers.size();
    s.truth.push_back(r);
    s.markers.push_back(m);
    s.poses.push_back(pose);
  }
  return s;
}

inline double ErrorDeg(const BodyPose& pose, const Eigen::Matrix3d& truth) {
  return pose.orientation.angularDistance(Eigen::Quaterniond(truth)) / kDeg;
}

inline double Median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// 300 deg/s about a slowly wandering axis at 100 Hz, as the simulator spins its bodies.
inline Eigen::Matrix3d Spinning(int f) {
  const double t = f / 100.0;
  const Eigen::Vector3d axis = Eigen::Vector3d(std::sin(0.7 * t), std::cos(0.9 * t), 0.6).normalized();
  return Eigen::AngleAxisd(300.0 * kDeg * t, axis).toRotationMatrix();
}

}  // namespace mocap::body_test
