// Steady distances: rigid pairs are learned, pairs across a joint never are, a change of labels
// is learned anew, and what is not seen is forgotten.
#include "track/steady_distances.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

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

// A pair once learned is followed at any distance: labels that change to a steady distance
// beyond the radius are learned anew there, not left at the old distance (which a repair would
// then hold against the markers' own labels).
TEST(SteadyDistances, ALearnedPairIsFollowedBeyondTheRadius) {
  SteadyDistances distances(kRadius, kMaxSd, kTolerance);
  std::mt19937 rng(6);
  Feed(&distances, 0, 60, [](uint64_t) { return 30.0; }, &rng);
  Feed(&distances, 60, 200, [](uint64_t) { return 80.0; }, &rng);
  const auto of_0 = NeighboursOf(distances, 0);
  ASSERT_EQ(of_0.size(), 1u);
  EXPECT_NEAR(of_0[0].mean_mm, 80.0, 0.3);
}

// Neighbours come in the order their pairs were first seen, by row position, whatever the
// positions' order in space (the repair sums over them in that order).
TEST(SteadyDistances, NeighboursComeInTheOrderOfTheRow) {
  SteadyDistances distances(kRadius, kMaxSd, kTolerance);
  const std::vector<std::pair<int, double>> columns_at_x = {{5, 0.0}, {2, 40.0}, {9, -15.0}, {1, 20.0}};
  for (uint64_t f = 0; f < 20; ++f) {
    std::vector<TrackSample> row;
    for (const auto& [column, x] : columns_at_x) {
      row.push_back(Sample(column, f, Eigen::Vector3d(x + 3.0 * f, 100.0 + 0.01 * (f % 2) * column, 500.0)));
    }
    distances.Learn(f, row);
  }
  const auto columns = [&](int column) {
    std::vector<int> out;
    for (const auto& n : NeighboursOf(distances, column)) out.push_back(n.column);
    return out;
  };
  EXPECT_EQ(columns(5), (std::vector<int>{2, 9, 1}));
  EXPECT_EQ(columns(2), (std::vector<int>{5, 9, 1}));
  EXPECT_EQ(columns(1), (std::vector<int>{5, 2, 9}));
}

// A row costs about its close pairs: 100 rigid two-marker clusters (25 mm) scattered 150 mm or
// more apart through a 2 m x 1.8 m x 1 m volume are all learned, and no row computes more than
// a fifth of its 19900 pair distances (all of them were computed, in every row, before).
TEST(SteadyDistances, ARowComputesItsClosePairsNotAllPairs) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> x(0.0, 2000.0), y(0.0, 1800.0), z(0.0, 1000.0), unit(-1.0, 1.0);
  std::vector<Eigen::Vector3d> centres, offsets;
  while (centres.size() < 100) {
    const Eigen::Vector3d c(x(rng), y(rng), z(rng));
    if (std::all_of(centres.begin(), centres.end(), [&](const Eigen::Vector3d& o) { return (o - c).norm() > 150.0; })) {
      centres.push_back(c);
      offsets.push_back(12.5 * Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).normalized());
    }
  }
  SteadyDistances distances(kRadius, kMaxSd, kTolerance);
  const size_t all_pairs = 200 * 199 / 2;
  for (uint64_t f = 0; f < 30; ++f) {
    const Eigen::Vector3d drift(4.0 * f, 0.0, 1.0 * f);
    std::vector<TrackSample> row;
    for (size_t c = 0; c < centres.size(); ++c) {
      row.push_back(Sample(static_cast<int>(2 * c), f, centres[c] + drift + offsets[c]));
      row.push_back(Sample(static_cast<int>(2 * c + 1), f, centres[c] + drift - offsets[c]));
    }
    distances.Learn(f, row);
    EXPECT_LT(distances.distances_computed(), all_pairs / 5) << "frame " << f;
  }
  EXPECT_EQ(distances.num_pairs(), centres.size());
  for (size_t c = 0; c < centres.size(); ++c) {
    const auto of_c = NeighboursOf(distances, static_cast<int>(2 * c));
    ASSERT_EQ(of_c.size(), 1u) << "cluster " << c;
    EXPECT_EQ(of_c[0].column, static_cast<int>(2 * c + 1));
    EXPECT_NEAR(of_c[0].mean_mm, 25.0, 1e-6);
  }
}

}  // namespace
}  // namespace mocap
