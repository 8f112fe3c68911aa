// The whole-take steps without files: a set learned from one part of a synthetic motion names
// another part with shuffled anonymous columns (up axis given and detected alike); a rigid body
// defined from its first frame is fitted in every frame and its pivot column follows the truth.
#include "pipeline/take_outputs.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include <gtest/gtest.h>

#include "labels/marker_set_learning.h"
#include "simcore/synthetic_motion.h"

namespace mocap::pipeline {
namespace {

MarkerTrajectories NamedMotion(int frames) {
  SyntheticMotionOptions options;
  options.markers = 20;
  options.frames = frames;
  options.rate_hz = 100.0;
  MarkerTrajectories motion = MakeSyntheticMotion(options);
  for (size_t m = 0; m < motion.names.size(); ++m) motion.names[m] = "S" + std::to_string(m + 1);
  return motion;
}

// Frames [from, to) of `motion`, columns shuffled and named M001...
MarkerTrajectories AnonymousPart(const MarkerTrajectories& motion, size_t from, size_t to) {
  std::vector<size_t> order(motion.NumMarkers());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::shuffle(order.begin(), order.end(), std::mt19937(5));
  MarkerTrajectories out;
  out.rate_hz = motion.rate_hz;
  for (size_t c = 0; c < order.size(); ++c) out.names.push_back(DefaultMarkerName(c));
  for (size_t f = from; f < to; ++f) {
    const size_t row = out.AddFrame(motion.frame_numbers[f]);
    for (size_t c = 0; c < order.size(); ++c) out.At(row, c) = motion.At(f, order[c]);
  }
  return out;
}

// Named points of `named` that sit on the truth marker of their name, and all named points.
std::pair<size_t, size_t> RightNames(const MarkerTrajectories& named, const MarkerTrajectories& truth, size_t from) {
  size_t right = 0, all = 0;
  for (size_t c = 0; c < named.NumMarkers(); ++c) {
    const auto it = std::find(truth.names.begin(), truth.names.end(), named.names[c]);
    if (it == truth.names.end()) continue;
    const size_t m = static_cast<size_t>(it - truth.names.begin());
    for (size_t f = 0; f < named.NumFrames(); ++f) {
      if (!named.Has(f, c)) continue;
      ++all;
      right += (named.At(f, c) - truth.At(from + f, m)).norm() < 1e-6;
    }
  }
  return {right, all};
}

TEST(TakeOutputs, NameTakeNamesAnotherPartOfTheMotion) {
  const MarkerTrajectories motion = NamedMotion(400);
  MarkerTrajectories first = motion;
  first.frame_numbers.resize(200);
  first.points.resize(200 * motion.NumMarkers());
  const MarkerSet set = LearnMarkerSet({first}, {"first half"});
  for (const TakeLabeller labeller : {TakeLabeller::kTrial, TakeLabeller::kSubject}) {
    for (int up_axis : {2, -1}) {
      SCOPED_TRACE(labeller == TakeLabeller::kTrial ? "trial labeller" : "subject labeller");
      MarkerTrajectories take = AnonymousPart(motion, 200, 400);
      const TakeNaming naming = NameTake(set, up_axis, &take, labeller);
      EXPECT_EQ(take.NumFrames(), 200u);
      EXPECT_EQ(naming.set_markers, motion.NumMarkers());
      EXPECT_GE(naming.names_placed, 18u) << "up axis " << up_axis;
      EXPECT_EQ(naming.points, 200u * motion.NumMarkers());
      const auto [right, named] = RightNames(take, motion, 200);
      EXPECT_EQ(named, naming.named_points);
      EXPECT_GE(static_cast<double>(right), 0.9 * static_cast<double>(named)) << "up axis " << up_axis;
      EXPECT_NE(naming.Describe().find(std::to_string(naming.names_placed) + " of 20 names placed"), std::string::npos)
          << naming.Describe();
      // Only the subject model initialises and logs its decisions.
      EXPECT_EQ(naming.Describe().find("initialised at frame") != std::string::npos, labeller == TakeLabeller::kSubject);
      EXPECT_EQ(naming.decisions.empty(), labeller == TakeLabeller::kTrial);
      EXPECT_EQ(naming.init_frame >= 0, labeller == TakeLabeller::kSubject);
    }
  }
}

TEST(TakeOutputs, NameTakeRefusesASetThatCannotLabel) {
  MarkerTrajectories take = AnonymousPart(NamedMotion(50), 0, 50);
  EXPECT_THROW(NameTake(MarkerSet{}, 2, &take), std::invalid_argument);
  EXPECT_THROW(NameTake(MarkerSet{}, 2, &take, TakeLabeller::kSubject), std::invalid_argument);
}

TEST(TakeOutputs, FitTakeBodiesFollowsARigidBodyAndAddsItsPivot) {
  const std::vector<Eigen::Vector3d> shape = {{0, 0, 0}, {90, 0, 0}, {0, 60, 0}, {30, 20, 70}};
  MarkerTrajectories take;
  take.rate_hz = 100.0;
  take.names = {"A", "B", "C", "D", "loose"};
  std::vector<Eigen::Vector3d> pivots;
  for (int f = 0; f < 120; ++f) {
    const double t = 0.01 * f;
    const Eigen::Matrix3d r = Eigen::AngleAxisd(0.8 * t, Eigen::Vector3d::UnitZ()).toRotationMatrix() *
                              Eigen::AngleAxisd(0.3 * std::sin(2 * t), Eigen::Vector3d::UnitX()).toRotationMatrix();
    const Eigen::Vector3d at(200.0 * t, 50.0 * std::cos(t), 1000.0);
    const size_t row = take.AddFrame(static_cast<uint64_t>(f));
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (size_t m = 0; m < shape.size(); ++m) {
      take.At(row, m) = at + r * shape[m];
      centroid += take.At(row, m) / static_cast<double>(shape.size());
    }
    take.At(row, 4) = Eigen::Vector3d(-500.0 + 3.0 * f, 400.0, 900.0);
    pivots.push_back(centroid);
  }
  std::vector<Eigen::Vector3d> first(shape.size());
  for (size_t m = 0; m < shape.size(); ++m) first[m] = take.At(0, m);
  const std::vector<RigidBodyDefinition> bodies = {DefineBody("probe", first)};
  const TakeBodies fitted = FitTakeBodies(bodies, BodySmoothingOptions(), &take);
  ASSERT_EQ(fitted.rows.size(), 120u);
  EXPECT_EQ(fitted.FramesFitted(0), 120u);
  ASSERT_EQ(fitted.smoothing.size(), 1u);
  ASSERT_EQ(take.NumMarkers(), 6u);
  EXPECT_EQ(take.names.back(), "probe");
  for (size_t f = 0; f < take.NumFrames(); ++f) {
    ASSERT_TRUE(take.Has(f, 5)) << "frame " << f;
    EXPECT_LT((take.At(f, 5) - pivots[f]).norm(), 1e-6) << "frame " << f;
  }
  EXPECT_EQ(fitted.MissSummary(0), "");
}

// Where a body is not fitted, the take says why, frame counts by cause.
TEST(TakeOutputs, ABodyNotFittedIsGivenItsReasons) {
  const std::vector<Eigen::Vector3d> shape = {{0, 0, 0}, {90, 0, 0}, {0, 60, 0}, {30, 20, 70}};
  MarkerTrajectories take;
  take.rate_hz = 100.0;
  take.names = {"A", "B", "C", "D"};
  for (int f = 0; f < 60; ++f) {
    const size_t row = take.AddFrame(static_cast<uint64_t>(f));
    // Frames 20-39: two markers hidden; frames 40-59: the shape stretched by a fifth.
    const double scale = f >= 40 ? 1.2 : 1.0;
    for (size_t m = 0; m < shape.size(); ++m)
      if (f < 20 || f >= 40 || m < 2) take.At(row, m) = Eigen::Vector3d(2.0 * f, 0, 1000) + scale * shape[m];
  }
  std::vector<Eigen::Vector3d> first(shape.size());
  for (size_t m = 0; m < shape.size(); ++m) first[m] = take.At(0, m);
  const TakeBodies fitted = FitTakeBodies({DefineBody("probe", first)}, BodySmoothingOptions(), &take);
  EXPECT_EQ(fitted.FramesFitted(0), 20u);
  EXPECT_EQ(fitted.MissSummary(0),
            "20 frames: too few free points in the frame; 20 frames: no three points with the sides of its triangles");
}

}  // namespace
}  // namespace mocap::pipeline
