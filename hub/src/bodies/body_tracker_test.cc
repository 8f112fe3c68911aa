// Rigid bodies in a crowd: two bodies and loose markers moving close together, with noise,
// single-marker occlusions, a stray point near a body's marker, and a whole body hidden for a few
// frames (predicted) and then found again; identity never swaps and poses stay within the
// noise.
#include "bodies/body_tracker.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

namespace mocap {
namespace {

struct Truth {
  Eigen::Matrix3d r;
  Eigen::Vector3d t;
};

Truth Motion(int body, int frame) {
  const double s = frame * 0.01;
  Truth out;
  out.r = (Eigen::AngleAxisd(0.8 * s + body, Eigen::Vector3d::UnitZ()) *
           Eigen::AngleAxisd(0.3 * std::sin(2 * s + body), Eigen::Vector3d::UnitX()))
              .toRotationMatrix();
  // The two bodies pass within 150 mm of each other.
  out.t = Eigen::Vector3d(400.0 * std::cos(s + 1.5 * body), 300.0 * std::sin(s), 1000.0 + 100 * body);
  return out;
}

double AngleDeg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a * b.transpose()).angle() * 180.0 / M_PI;
}

TEST(BodyTracker, TwoBodiesAndLooseMarkersThroughOcclusions) {
  const std::vector<RigidBodyDefinition> bodies = {
      DefineBody("wand", {{0, 0, 0}, {120, 0, 0}, {0, 80, 0}, {40, 30, 50}}),
      DefineBody("drone", {{0, 0, 0}, {150, 0, 0}, {30, 110, 0}, {70, 40, -35}, {-40, 60, 20}})};
  BodyTracker tracker(bodies);
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, 0.1);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int tracked = 0, predicted = 0, frames = 0;
  double worst_mm = 0.0, worst_deg = 0.0;
  for (int f = 0; f < 400; ++f) {
    std::vector<Eigen::Vector3d> points;
    std::vector<std::pair<int, int>> truth_of_point;  // (body, marker), (-1, -1) for loose
    const bool drone_hidden = f >= 200 && f < 206;
    int visible[2] = {0, 0};
    for (int b = 0; b < 2; ++b) {
      const Truth t = Motion(b, f);
      for (size_t m = 0; m < bodies[static_cast<size_t>(b)].markers.size(); ++m) {
        if (b == 1 && drone_hidden) continue;
        if (u(rng) < 0.05) continue;  // one marker hidden now and then
        ++visible[b];
        points.push_back(t.r * bodies[static_cast<size_t>(b)].markers[m] + t.t +
                         Eigen::Vector3d(noise(rng), noise(rng), noise(rng)));
        truth_of_point.emplace_back(b, static_cast<int>(m));
      }
    }
    for (int k = 0; k < 40; ++k) {  // loose markers: a person walking past, and one near the wand
      points.push_back(Eigen::Vector3d(300.0 * std::cos(0.2 * k + 0.01 * f), 300.0 * std::sin(0.3 * k), 900.0 + 10 * k));
      truth_of_point.emplace_back(-1, -1);
    }
    // A stray point 15 mm from one of the wand's markers: inside the tracking gate, outside the
    // fit's tolerance, so it must be rejected when that marker is hidden.
    const Truth wand = Motion(0, f);
    points.push_back(wand.r * (bodies[0].markers[3] + Eigen::Vector3d(15, 0, 0)) + wand.t);
    truth_of_point.emplace_back(-1, -1);
    // Shuffled: order carries no identity.
    std::vector<size_t> order(points.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::shuffle(order.begin(), order.end(), rng);
    std::vector<Eigen::Vector3d> shuffled;
    for (size_t i : order) shuffled.push_back(points[i]);
    std::vector<int> owner;
    const std::vector<BodyPose> poses = tracker.Update(shuffled, &owner);
    ++frames;
    for (int b = 0; b < 2; ++b) {
      const BodyPose& p = poses[static_cast<size_t>(b)];
      const Truth t = Motion(b, f);
      if (visible[b] < 3) {  // hidden (or all but two markers hidden): predicted, not fitted
        EXPECT_FALSE(p.tracked) << f;
        EXPECT_TRUE(p.predicted) << f;
        predicted += p.predicted;
        EXPECT_LT((p.position - t.t).norm(), 10.0) << "prediction at frame " << f;
        continue;
      }
      ASSERT_TRUE(p.tracked) << "body " << b << " frame " << f;
      ++tracked;
      worst_mm = std::max(worst_mm, (p.position - t.t).norm());
      worst_deg = std::max(worst_deg, AngleDeg(p.orientation.toRotationMatrix(), t.r));
      EXPECT_LT(p.mean_error_mm, 0.5);
      // Identity: every point the body took is one of its own markers, in the right slot.
      for (size_t m = 0; m < p.point_of_marker.size(); ++m) {
        const int q = p.point_of_marker[m];
        if (q < 0) continue;
        EXPECT_EQ(truth_of_point[order[static_cast<size_t>(q)]], std::make_pair(b, static_cast<int>(m))) << f;
        EXPECT_EQ(owner[static_cast<size_t>(q)], b);
      }
    }
  }
  EXPECT_GE(predicted, 6);
  EXPECT_GE(tracked, 2 * 400 - predicted);
  EXPECT_LT(worst_mm, 0.5);
  EXPECT_LT(worst_deg, 0.5);
  std::printf("bodies: %d poses, worst %.3f mm / %.3f deg\n", tracked, worst_mm, worst_deg);
}

TEST(BodyTracker, NothingFromLooseMarkersAlone) {
  BodyTracker tracker({DefineBody("wand", {{0, 0, 0}, {120, 0, 0}, {0, 80, 0}, {40, 30, 50}})});
  std::vector<Eigen::Vector3d> points;
  for (int k = 0; k < 60; ++k) points.push_back(Eigen::Vector3d(37.0 * k, 11.0 * (k % 7), 5.0 * (k % 3)));
  EXPECT_FALSE(tracker.Update(points)[0].tracked);
  EXPECT_FALSE(tracker.Update({})[0].tracked);
}

// A body not fitted says why: nothing there, points that do not have its shape, its triangle
// without the rest of it, or a frame too crowded to search.
TEST(BodyTracker, AMissSaysWhy) {
  const std::vector<Eigen::Vector3d> shape{{0, 0, 0}, {120, 0, 0}, {0, 80, 0}, {40, 30, 50}, {90, 60, 20}};
  BodyTrackerOptions options;
  options.max_points = 20;
  BodyTracker tracker({DefineBody("wand", shape)}, options);
  EXPECT_EQ(tracker.Update({shape[0], shape[1]})[0].miss, BodyMiss::kTooFewPoints);
  // Five points, none three with its sides (a skin cluster that stretched by 10 %).
  std::vector<Eigen::Vector3d> stretched;
  for (const Eigen::Vector3d& p : shape) stretched.push_back(1.1 * p);
  EXPECT_EQ(tracker.Update(stretched)[0].miss, BodyMiss::kNoShape);
  // Its first three markers in place, the other two moved away: the triangle places it, the
  // rest is missing.
  std::vector<Eigen::Vector3d> partial = shape;
  partial[3] += Eigen::Vector3d(0, 0, 40);
  partial[4] += Eigen::Vector3d(0, 45, 0);
  const BodyPose miss = tracker.Update(partial)[0];
  EXPECT_FALSE(miss.tracked);
  EXPECT_EQ(miss.miss, BodyMiss::kTooFewMarkers);
  std::vector<Eigen::Vector3d> crowd = shape;
  for (int k = 0; k < 30; ++k) crowd.push_back(Eigen::Vector3d(1000.0 + 37.0 * k, 0, 0));
  EXPECT_EQ(tracker.Update(crowd)[0].miss, BodyMiss::kCrowded);
  const BodyPose fitted = tracker.Update(shape)[0];
  EXPECT_TRUE(fitted.tracked);
  EXPECT_EQ(fitted.miss, BodyMiss::kNone);
  EXPECT_STREQ(BodyMissText(BodyMiss::kNoShape), "no three points with the sides of its triangles");
}

TEST(BodyTracker, OptionsChecked) {
  BodyTrackerOptions o;
  o.min_markers_start = 2;
  EXPECT_THROW(BodyTracker({}, o), std::invalid_argument);
}

}  // namespace
}  // namespace mocap
