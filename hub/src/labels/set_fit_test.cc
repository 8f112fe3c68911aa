// The set placed on one frame with no history: another subject's size and heading, on a body
// whose left and right sides are mirror images (every distance alike: only the handedness of the
// fit, a proper rotation, tells them apart).
#include "labels/set_fit.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "labels/marker_set_learning.h"

namespace mocap {
namespace {

// A standing body, symmetric about x = 0 but for the trunk's front and back (the chest marker
// sits lower than the back one); each arm a rigid cluster of three markers off the body.
MarkerTrajectories SymmetricBody() {
  MarkerTrajectories motion;
  motion.rate_hz = 100.0;
  motion.names = {"Front", "Back", "Head", "L.Shoulder", "L.Elbow", "L.Wrist", "R.Shoulder", "R.Elbow", "R.Wrist",
                  "L.Knee", "R.Knee"};
  const std::vector<Eigen::Vector3d> rest = {{0, 110, 1300},    {0, -100, 1380},   {0, 0, 1700},
                                             {-190, 0, 1450},   {-420, 40, 1380},  {-470, 140, 1250},
                                             {190, 0, 1450},    {420, 40, 1380},   {470, 140, 1250},
                                             {-110, 40, 500},   {110, 40, 500}};
  for (int f = 0; f < 40; ++f) {
    const size_t row = motion.AddFrame(static_cast<uint64_t>(f));
    const double sway = 3.0 * std::sin(0.3 * f);  // a little life so that distances have spread
    for (size_t m = 0; m < rest.size(); ++m) motion.At(row, m) = rest[m] + Eigen::Vector3d(sway, 0.5 * sway, 0.0);
  }
  return motion;
}

TEST(SetFit, AnotherSizeAndHeadingIsNamedLeftAsLeft) {
  const MarkerTrajectories motion = SymmetricBody();
  MarkerSet set = LearnMarkerSet({motion}, {"body"});
  set.Index();
  // Turned by 170 degrees (facing the other way: a distance-only match cannot tell left from
  // right), 12 % larger, moved, in another order.
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(170.0 * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const std::vector<size_t> order = {5, 2, 9, 0, 7, 3, 10, 1, 8, 4, 6};
  std::vector<Eigen::Vector3d> points;
  for (size_t m : order) points.push_back(1.12 * (turn * motion.At(0, m)) + Eigen::Vector3d(2000, -500, 0));
  const SetFit fit = FitSetToFrame(set, points);
  ASSERT_EQ(fit.labels.size(), points.size());
  for (size_t p = 0; p < points.size(); ++p) {
    ASSERT_GE(fit.labels[p], 0) << "point of " << motion.names[order[p]] << " unnamed";
    EXPECT_EQ(set.names[static_cast<size_t>(fit.labels[p])], motion.names[order[p]]);
  }
  EXPECT_NEAR(fit.scale, 1.12, 0.03);
}

TEST(SetFit, RefusesBadOptionsNamingTheField) {
  MarkerSet set = LearnMarkerSet({SymmetricBody()}, {"body"});
  set.Index();
  SetFitOptions bad;
  bad.ambiguity_ratio = 0.5;
  try {
    FitSetToFrame(set, {}, bad);
    ADD_FAILURE() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("ambiguity_ratio"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace mocap
