// Steady distances: rigid pairs are learned, pairs across a joint never are, a change of labels
// is learned anew, and what is not seen is forgotten.
#include "track/steady_distances.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

namespace mocap {
namespace {

constexpr double kRadius = 60.0, kMaxSd = 1.5, kTolerance = 2.0;

TrackSample Sample(int column, uint64_t frame, const Eigen::Vector3d& position,
                   SampleKind kind = SampleKind::kMeasured) {
  TrackSample s;
  s.marker = column;
  s.frame_number = frame;
  s.position = position;
  s.kind = kind;
  return s;
}

// Column 0 moves; column 1 is `distance(frame)` from it along a turning direction, with noise.
template <typename Distance>
void Feed(SteadyDistances* distances, uint64_t from, uint64_t to, Distance distance, std::mt19937* rng,
          SampleKind kind = SampleKind::kMeasured) {
  std::normal_distribution<double> noise(0.0, 0.3);
  for (uint64_t f = from; f < to; ++f) {
    const double angle = 0.05 * static_cast<double>(f);
    const Eigen::Vector3d a(5.0 * f, 100.0, 0.0);
    const Eigen::Vector3d direction(std::cos(angle), std::sin(angle), 0.0);
    const Eigen::Vector3d b = a + distance(f) * direction + Eigen::Vector3d(noise(*rng), noise(*rng), noise(*rng));
    distances->Learn(f, {Sample(0, f, a, kind), Sample(1, f, b, kind)});
  }
}

std::vector<SteadyDistances::Neighbour> NeighboursOf(const SteadyDistances& distances, int column) {
  std::vector<SteadyDistances::Neighbour> out;
  distances.SteadyNeighbours(column, &out);
  return out;
}

TEST(SteadyDistances, RigidPairIsLearnedAfterEnoughFrames) {
  SteadyDistances distances(kRadius, kMaxSd, kTolerance);
  std::mt19937 rng(1);
  Feed(&distances, 0, SteadyDistances::kMinSamples - 1, [](uint64_t) { return 25.0; }, &rng);
  EXPECT_TRUE(NeighboursOf(distances, 0).empty());
  Feed(&distances, SteadyDistances::kMinSamples - 1, 60, [](uint64_t) { return 25.0; }, &rng);
  const auto of_0 = NeighboursOf(distances, 0);
  ASSERT_EQ(of_0.size(), 1u);
  EXPECT_EQ(of_0[0].column, 1);
  EXPECT_NEAR(of_0[0].mean_mm, 25.0, 0.3);
  EXPECT_GE(of_0[0].tolerance_mm, kTolerance);
  ASSERT_EQ(NeighboursOf(distances, 1).size(), 1u);
  EXPECT_EQ(NeighboursOf(distances, 1)[0].column, 0);
  EXPECT_EQ(SteadyDistances::Excess(of_0[0], of_0[0].mean_mm + of_0[0].tolerance_mm - 0.1), 0.0);
  EXPECT_NEAR(SteadyDistances::Excess(of_0[0], of_0[0].mean_mm - of_0[0].tolerance_mm - 3.0), 9.0, 1e-9);
}

TEST(SteadyDistances, FarPairsPredictionsAndStrangersAreNotLearned) {
  SteadyDistances distances(kRadius, kMaxSd, kTolerance);
  std::mt19937 rng(2);
  Feed(&distances, 0, 100, [](uint64_t) { return 80.0; }, &rng);
  EXPECT_EQ(distances.num_pairs(), 0u);
  Feed(&distances, 100, 200, [](uint64_t) { return 25.0; }, &rng, SampleKind::kPredicted);
  EXPECT_EQ(distances.num_pairs(), 0u);
  EXPECT_TRUE(NeighboursOf(distances, 7).empty());
  EXPECT_TRUE(NeighboursOf(distances, -1).empty());
}

TEST(SteadyDistances, PairAcrossAJointIsNeverSteady) {
  SteadyDistances distances(kRadius, kMaxSd, kTolerance);
  std::mt19937 rng(3);
  // Still for a while (steady), then the joint bends slowly, then still again.
  Feed(&distances, 0, 200, [](uint64_t f) { return f < 60 ? 30.0 : f < 90 ? 30.0 + 0.5 * (f - 60.0) : 45.0; }, &rng);
  EXPECT_TRUE(NeighboursOf(distances, 0).empty());
}

TEST(SteadyDistances, ChangedLabelsAreLearnedAnew) {
  SteadyDistances distances(kRadius, kMaxSd, kTolerance);
  std::mt19937 rng(4);
  Feed(&distances, 0, 60, [](uint64_t) { return 20.0; }, &rng);
  // The labels change: the distance steps to another steady value.
  Feed(&distances, 60, 60 + SteadyDistances::kMaxStrays - 1, [](uint64_t) { return 30.0; }, &rng);
  auto of_0 = NeighboursOf(distances, 0);
  ASSERT_EQ(of_0.size(), 1u);
  EXPECT_NEAR(of_0[0].mean_mm, 20.0, 0.3);  // still the old one: it may be traded back
  Feed(&distances, 60 + SteadyDistances::kMaxStrays - 1, 200, [](uint64_t) { return 30.0; }, &rng);
  of_0 = NeighboursOf(distances, 0);
  ASSERT_EQ(of_0.size(), 1u);
  EXPECT_NEAR(of_0[0].mean_mm, 30.0, 0.3);
}

TEST(SteadyDistances, PairsUnseenForLongAreForgotten) {
  SteadyDistances distances(kRadius, kMaxSd, kTolerance);
  std::mt19937 rng(5);
  Feed(&distances, 0, 60, [](uint64_t) { return 20.0; }, &rng);
  EXPECT_EQ(distances.num_pairs(), 1u);
  // Other columns only, for long.
  for (uint64_t f = 60; f < 60 + 2 * SteadyDistances::kForgetFrames + 2; ++f) {
    distances.Learn(f, {Sample(5, f, Eigen::Vector3d(0, 0, 0)), Sample(6, f, Eigen::Vector3d(0, 0, 25.0))});
  }
  EXPECT_EQ(distances.num_pairs(), 1u);  // 5-6 only
  EXPECT_TRUE(NeighboursOf(distances, 0).empty());
  EXPECT_EQ(NeighboursOf(distances, 5).size(), 1u);
}

}  // namespace
}  // namespace mocap
