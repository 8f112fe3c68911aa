// Labelling: a set learned from a labelled synthetic motion names another part of that motion
// with shuffled, anonymous columns; a swap between two tracks costs the names (never carried
// across); the frame-by-frame labeller names points by their tracks.
#include <algorithm>
#include <random>

#include <gtest/gtest.h>

#include "labels/marker_labeller.h"
#include "labels/marker_set_learning.h"
#include "labels/trial_labeller.h"
#include "simcore/synthetic_motion.h"

namespace mocap {
namespace {

MarkerTrajectories Motion(int frames, uint64_t first_frame) {
  SyntheticMotionOptions options;
  options.markers = 20;
  options.frames = frames;
  options.rate_hz = 100.0;
  options.first_frame = first_frame;
  MarkerTrajectories motion = MakeSyntheticMotion(options);
  for (size_t m = 0; m < motion.names.size(); ++m) motion.names[m] = "S" + std::to_string(m + 1);
  return motion;
}

// The frames [from, to) with the columns in another order and anonymous names; order[c] is the
// source column of output column c.
MarkerTrajectories Anonymous(const MarkerTrajectories& motion, size_t from, size_t to, std::vector<size_t>* order) {
  order->resize(motion.NumMarkers());
  for (size_t i = 0; i < order->size(); ++i) (*order)[i] = i;
  std::shuffle(order->begin(), order->end(), std::mt19937(7));
  MarkerTrajectories out;
  out.rate_hz = motion.rate_hz;
  for (size_t c = 0; c < order->size(); ++c) out.names.push_back(DefaultMarkerName(c));
  for (size_t f = from; f < to; ++f) {
    const size_t row = out.AddFrame(motion.frame_numbers[f]);
    for (size_t c = 0; c < order->size(); ++c) out.At(row, c) = motion.At(f, (*order)[c]);
  }
  return out;
}

// Share of the output's named points that sit on the truth marker of their name.
double CorrectShare(const TrialLabelling& result, const MarkerTrajectories& motion, size_t from) {
  size_t correct = 0, named = 0;
  for (size_t c = 0; c < result.named.NumMarkers(); ++c) {
    const auto it = std::find(motion.names.begin(), motion.names.end(), result.named.names[c]);
    if (it == motion.names.end()) continue;
    const size_t truth = static_cast<size_t>(it - motion.names.begin());
    for (size_t f = 0; f < result.named.NumFrames(); ++f) {
      if (!result.named.Has(f, c)) continue;
      ++named;
      correct += (result.named.At(f, c) - motion.At(from + f, truth)).norm() < 1e-6;
    }
  }
  return named ? static_cast<double>(correct) / named : 0.0;
}

TEST(TrialLabeller, NamesAnotherPartOfTheMotion) {
  const MarkerTrajectories motion = Motion(400, 0);
  MarkerTrajectories first = motion;
  first.frame_numbers.resize(200);
  first.points.resize(200 * motion.NumMarkers());
  const MarkerSet set = LearnMarkerSet({first}, {"first half"});
  std::vector<size_t> order;
  const MarkerTrajectories second = Anonymous(motion, 200, 400, &order);
  LabellerOptions options;
  options.up_axis = 2;
  const TrialLabelling result = LabelTrajectories(second, set, options);
  EXPECT_GE(result.names_placed, 18u);
  EXPECT_GE(CorrectShare(result, motion, 200), 0.9);
  EXPECT_EQ(result.points, 200u * motion.NumMarkers());
}

TEST(TrialLabeller, ASwapCostsTheNameAfterIt) {
  const MarkerTrajectories motion = Motion(300, 0);
  const MarkerSet set = LearnMarkerSet({motion}, {"motion"});
  std::vector<size_t> order;
  MarkerTrajectories swapped = Anonymous(motion, 0, 300, &order);
  // Two columns of one segment exchange their markers from frame 150 on, as a tracker swap would.
  ASSERT_FALSE(set.segments.empty());
  const int a = set.segments[0][0], b = set.segments[0][1];
  const size_t ca = static_cast<size_t>(std::find(order.begin(), order.end(), static_cast<size_t>(a)) - order.begin());
  const size_t cb = static_cast<size_t>(std::find(order.begin(), order.end(), static_cast<size_t>(b)) - order.begin());
  for (size_t f = 150; f < 300; ++f) std::swap(swapped.At(f, ca), swapped.At(f, cb));
  LabellerOptions options;
  options.up_axis = 2;
  const TrialLabelling result = LabelTrajectories(swapped, set, options);
  EXPECT_GT(result.stats.revocations, 0);
  // No point is carried under a wrong name over the swap: every named point of a and b is right.
  for (int marker : {a, b}) {
    const auto column = std::find(result.named.names.begin(), result.named.names.end(), set.names[static_cast<size_t>(marker)]);
    if (column == result.named.names.end()) continue;
    const size_t c = static_cast<size_t>(column - result.named.names.begin());
    size_t wrong = 0;
    for (size_t f = 0; f < 300; ++f)
      wrong += result.named.Has(f, c) && (result.named.At(f, c) - motion.At(f, static_cast<size_t>(marker))).norm() > 1e-6;
    EXPECT_LE(wrong, 2u) << set.names[static_cast<size_t>(marker)];
  }
}

TEST(TrialLabeller, AnotherSubjectsClusterWithOtherSidesKeepsItsNames) {
  // Another subject: 8 % larger, and one marker of a segment sits 30 % farther from its segment's
  // centre (still rigid with it): its distances to its partners are not the set's, but they are
  // steady, so the frame check (against this subject's own distances) must not take its name.
  const MarkerTrajectories motion = Motion(400, 0);
  MarkerTrajectories first = motion;
  first.frame_numbers.resize(200);
  first.points.resize(200 * motion.NumMarkers());
  const MarkerSet set = LearnMarkerSet({first}, {"first half"});
  ASSERT_FALSE(set.segments.empty());
  const std::vector<int>* segment = &set.segments[0];
  for (const std::vector<int>& s : set.segments)
    if (s.size() > segment->size()) segment = &s;
  ASSERT_GE(segment->size(), 3u);
  const size_t moved = static_cast<size_t>((*segment)[0]);
  MarkerTrajectories other = motion;
  for (size_t f = 0; f < other.NumFrames(); ++f) {
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (int m : *segment) centre += motion.At(f, static_cast<size_t>(m)) / static_cast<double>(segment->size());
    other.At(f, moved) = centre + 1.3 * (motion.At(f, moved) - centre);
    for (size_t m = 0; m < other.NumMarkers(); ++m) other.At(f, m) *= 1.08;
  }
  std::vector<size_t> order;
  const MarkerTrajectories second = Anonymous(other, 200, 400, &order);
  LabellerOptions options;
  options.up_axis = 2;
  const TrialLabelling result = LabelTrajectories(second, set, options);
  const auto column = std::find(result.named.names.begin(), result.named.names.end(), set.names[moved]);
  ASSERT_NE(column, result.named.names.end());
  const size_t c = static_cast<size_t>(column - result.named.names.begin());
  size_t right = 0;
  for (size_t f = 0; f < 200; ++f) right += result.named.Has(f, c) && (result.named.At(f, c) - other.At(200 + f, moved)).norm() < 1e-6;
  EXPECT_GE(right, 190u);
  EXPECT_GE(CorrectShare(result, other, 200), 0.95);
}

// A walking trunk with an arm swinging fast whose markers sit on soft tissue (18 mm of jitter
// each): none of the arm's distances is steady, so only how well each point fits its name
// against the others can tell that the tracker swapped two of them.
MarkerTrajectories LooseArm(int frames) {
  MarkerTrajectories motion;
  motion.rate_hz = 100.0;
  motion.names = {"T1", "T2", "T3", "T4", "Shoulder", "Elbow", "Wrist", "Hand"};
  std::mt19937 random(11);
  std::normal_distribution<double> jitter(0.0, 18.0);
  const std::vector<Eigen::Vector3d> trunk = {{0, -120, 1000}, {0, 120, 1000}, {-60, 0, 1300}, {40, 0, 1450}};
  for (int f = 0; f < frames; ++f) {
    const double t = f / motion.rate_hz;
    const Eigen::Vector3d centre(1000.0 * t, 0.0, 0.0);
    const size_t row = motion.AddFrame(static_cast<uint64_t>(f));
    for (size_t m = 0; m < trunk.size(); ++m) motion.At(row, m) = centre + trunk[m];
    const Eigen::Vector3d shoulder = centre + Eigen::Vector3d(0, 200, 1400);
    const double upper = 0.9 * std::sin(2.0 * M_PI * 1.1 * t), lower = upper + 0.7 + 0.6 * std::sin(2.0 * M_PI * 1.1 * t + 1.0);
    const Eigen::Vector3d elbow = shoulder + 300.0 * Eigen::Vector3d(std::sin(upper), 0.15, -std::cos(upper));
    const Eigen::Vector3d wrist = elbow + 260.0 * Eigen::Vector3d(std::sin(lower), 0.1, -std::cos(lower));
    const Eigen::Vector3d hand = wrist + 90.0 * Eigen::Vector3d(std::sin(lower + 0.3), 0.0, -std::cos(lower + 0.3));
    motion.At(row, 4) = shoulder;
    motion.At(row, 5) = elbow + Eigen::Vector3d(jitter(random), jitter(random), jitter(random));
    motion.At(row, 6) = wrist + Eigen::Vector3d(jitter(random), jitter(random), jitter(random));
    motion.At(row, 7) = hand + Eigen::Vector3d(jitter(random), jitter(random), jitter(random));
  }
  return motion;
}

TEST(TrialLabeller, ASwapOfMarkersWithoutSteadyPartnersIsRenamed) {
  const MarkerTrajectories motion = LooseArm(300);
  const MarkerSet set = LearnMarkerSet({motion}, {"loose arm"});
  for (const char* name : {"Elbow", "Wrist"}) {
    const int m = set.Find(name);
    for (const MarkerDistance& d : set.distances) {
      if (d.a == m || d.b == m) {
        ASSERT_GT(d.sd, 15.0) << name << " has a steady partner";
      }
    }
  }
  std::vector<size_t> order;
  MarkerTrajectories swapped = Anonymous(motion, 0, 300, &order);
  const size_t elbow = static_cast<size_t>(std::find(order.begin(), order.end(), 5u) - order.begin());
  const size_t wrist = static_cast<size_t>(std::find(order.begin(), order.end(), 6u) - order.begin());
  for (size_t f = 200; f < 300; ++f) std::swap(swapped.At(f, elbow), swapped.At(f, wrist));
  LabellerOptions options;
  options.up_axis = 2;
  const TrialLabelling result = LabelTrajectories(swapped, set, options);
  for (size_t marker : {5u, 6u}) {
    const auto column = std::find(result.named.names.begin(), result.named.names.end(), set.names[marker]);
    ASSERT_NE(column, result.named.names.end());
    const size_t c = static_cast<size_t>(column - result.named.names.begin());
    size_t right = 0, wrong = 0;
    for (size_t f = 0; f < 300; ++f) {
      if (!result.named.Has(f, c)) continue;
      ((result.named.At(f, c) - motion.At(f, marker)).norm() < 1e-6 ? right : wrong)++;
    }
    EXPECT_LE(wrong, 5u) << set.names[marker];
    EXPECT_GE(right, 270u) << set.names[marker];  // renamed after the swap, not only left unnamed
  }
}

TEST(MarkerLabeller, NamesFollowTracksFrameByFrame) {
  const MarkerTrajectories motion = Motion(200, 0);
  const MarkerSet set = LearnMarkerSet({motion}, {"motion"});
  LabellerOptions options;  // up axis searched, as live
  MarkerLabeller labeller(set, options);
  size_t correct = 0, wrong = 0;
  for (size_t f = 0; f < motion.NumFrames(); ++f) {
    std::vector<Eigen::Vector3d> points;
    std::vector<int64_t> tracks;
    for (size_t m = 0; m < motion.NumMarkers(); ++m) points.push_back(motion.At(f, m)), tracks.push_back(100 + static_cast<int64_t>(m));
    const std::vector<int>& labels = labeller.Update(points, tracks);
    for (size_t m = 0; m < labels.size(); ++m)
      if (labels[m] >= 0) (static_cast<size_t>(labels[m]) == m ? correct : wrong)++;
  }
  EXPECT_GT(correct, motion.NumFrames() * motion.NumMarkers() * 8 / 10);
  EXPECT_LT(wrong, correct / 20);
}

TEST(MarkerLabeller, RefusesBadInput) {
  MarkerSet empty;
  empty.names = {"a", "b"};
  empty.mean_shape.assign(2, Eigen::Vector3d::Constant(std::nan("")));
  EXPECT_THROW(MarkerLabeller{empty}, std::invalid_argument);
  const MarkerSet set = LearnMarkerSet({Motion(50, 0)}, {"m"});
  MarkerLabeller labeller(set);
  EXPECT_THROW(labeller.Update({Eigen::Vector3d::Zero()}, {}), std::invalid_argument);
  LabellerOptions bad;
  bad.min_vote_share = 2.0;
  EXPECT_THROW(MarkerLabeller(set, bad), std::invalid_argument);
}

}  // namespace
}  // namespace mocap
