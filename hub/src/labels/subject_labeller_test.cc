// Offline labelling of whole recordings: a set learned from a labelled synthetic motion names
// another part of it, another (larger, other proportions) subject and a long trial, with shuffled
// anonymous columns; a swap between two tracks is never carried under a wrong name; every
// decision is logged.
#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <utility>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "labels/marker_set_learning.h"
#include "labels/subject_labeller.h"
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
double CorrectShare(const SubjectLabelling& result, const MarkerTrajectories& motion, size_t from) {
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

// The motion with its columns cut at gaps, as a tracker delivers a long trial: every marker is
// hidden for `gap` frames every `every` frames (its phase set by the marker), and comes back in a
// new column. Columns are anonymous. truth[c] is the source marker of column c.
MarkerTrajectories WithGaps(const MarkerTrajectories& motion, size_t every, size_t gap, std::vector<size_t>* truth) {
  MarkerTrajectories out;
  out.rate_hz = motion.rate_hz;
  truth->clear();
  std::vector<std::vector<std::pair<size_t, size_t>>> pieces(motion.NumMarkers());
  for (size_t m = 0; m < motion.NumMarkers(); ++m) {
    size_t start = 0;
    for (size_t cut = (37 * m) % every + every / 2; cut + gap < motion.NumFrames(); cut += every) {
      pieces[m].push_back({start, cut});
      start = cut + gap;
    }
    pieces[m].push_back({start, motion.NumFrames()});
    for (size_t i = 0; i < pieces[m].size(); ++i) truth->push_back(m);
  }
  for (size_t c = 0; c < truth->size(); ++c) out.names.push_back(DefaultMarkerName(c));
  for (size_t f = 0; f < motion.NumFrames(); ++f) out.AddFrame(motion.frame_numbers[f]);
  size_t column = 0;
  for (size_t m = 0; m < motion.NumMarkers(); ++m)
    for (const auto& [from, to] : pieces[m]) {
      for (size_t f = from; f < to; ++f) out.At(f, column) = motion.At(f, m);
      ++column;
    }
  return out;
}

// Right and wrong named points of a labelling against the motion it came from (same frames).
std::pair<size_t, size_t> RightAndWrong(const SubjectLabelling& result, const MarkerTrajectories& motion) {
  size_t right = 0, wrong = 0;
  for (size_t c = 0; c < result.named.NumMarkers(); ++c) {
    const auto it = std::find(motion.names.begin(), motion.names.end(), result.named.names[c]);
    if (it == motion.names.end()) continue;
    const size_t truth = static_cast<size_t>(it - motion.names.begin());
    for (size_t f = 0; f < result.named.NumFrames(); ++f) {
      if (!result.named.Has(f, c)) continue;
      ((result.named.At(f, c) - motion.At(f, truth)).norm() < 1e-6 ? right : wrong)++;
    }
  }
  return {right, wrong};
}

TEST(SubjectLabeller, NamesAnotherPartOfTheMotion) {
  const MarkerTrajectories motion = Motion(400, 0);
  MarkerTrajectories first = motion;
  first.frame_numbers.resize(200);
  first.points.resize(200 * motion.NumMarkers());
  const MarkerSet set = LearnMarkerSet({first}, {"first half"});
  std::vector<size_t> order;
  const MarkerTrajectories second = Anonymous(motion, 200, 400, &order);
  SubjectLabellerOptions options;
  options.up_axis = 2;
  const SubjectLabelling result = LabelSubject(second, set, options);
  EXPECT_GE(result.names_placed, 18u);
  EXPECT_GE(CorrectShare(result, motion, 200), 0.9);
  EXPECT_EQ(result.points, 200u * motion.NumMarkers());
}

TEST(SubjectLabeller, ASwapCostsTheNameAfterIt) {
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
  SubjectLabellerOptions options;
  options.up_axis = 2;
  const SubjectLabelling result = LabelSubject(swapped, set, options);
  // The name taken at the swap is a decision in the log, with the frame.
  EXPECT_TRUE(std::any_of(result.decisions.begin(), result.decisions.end(), [](const std::string& line) {
    return line.find("loses") != std::string::npos;
  }));
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

TEST(SubjectLabeller, AnotherSubjectsClusterWithOtherSidesKeepsItsNames) {
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
  SubjectLabellerOptions options;
  options.up_axis = 2;
  // A marker the set places 30 % off (another subject) or a limb far from its mean pose: the
  // set's shape names it only with a wider refit gate than the default (which leaves it unnamed).
  options.refit_gate_mm = 100.0;
  options.refit_confirm = 2;
  const SubjectLabelling result = LabelSubject(second, set, options);
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

TEST(SubjectLabeller, ASwapOfMarkersWithoutSteadyPartnersIsNeverCarried) {
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
  SubjectLabellerOptions options;
  options.up_axis = 2;
  // A marker the set places 30 % off (another subject) or a limb far from its mean pose: the
  // set's shape names it only with a wider refit gate than the default (which leaves it unnamed).
  options.refit_gate_mm = 100.0;
  options.refit_confirm = 2;
  const SubjectLabelling result = LabelSubject(swapped, set, options);
  // The elbow is named before the swap and its name is not carried across it (no steady pair
  // can tell: the jump onto where the wrist was does); what cannot be placed after it stays
  // unnamed, never wrong.
  const auto [right, wrong] = RightAndWrong(result, motion);
  EXPECT_EQ(wrong, 0u);
  EXPECT_GT(right, 0u);  // not vacuous: the trunk is named
  // Where the elbow is named, its name never follows the marker onto the wrist's path. (Built by
  // gcc the elbow is named in 190 or more of the 200 frames before the swap; built by clang for
  // the ASan/UBSan run it is left unnamed here, deterministically, with no uninitialised read
  // under valgrind: a decision on a knife edge in this synthetic arm, not yet explained.)
  const auto column = std::find(result.named.names.begin(), result.named.names.end(), "Elbow");
  if (column != result.named.names.end()) {
    const size_t c = static_cast<size_t>(column - result.named.names.begin());
    for (size_t f = 200; f < 300; ++f)
      if (result.named.Has(f, c)) {
        EXPECT_LT((result.named.At(f, c) - motion.At(f, 5)).norm(), 1e-6) << "frame " << f;
      }
  }
}

TEST(SubjectLabeller, ALongTrialWithGapsIsNamedThroughout) {
  // 4000 frames, every marker hidden for 4 frames every 250: 16 runs per marker, 320 in all (the
  // former labeller's whole-trial search stopped at 2000 runs and fell with the trial's length).
  const MarkerTrajectories motion = Motion(4000, 0);
  MarkerTrajectories first = motion;
  first.frame_numbers.resize(300);
  first.points.resize(300 * motion.NumMarkers());
  const MarkerSet set = LearnMarkerSet({first}, {"first frames"});
  std::vector<size_t> truth;
  const MarkerTrajectories gapped = WithGaps(motion, 250, 4, &truth);
  SubjectLabellerOptions options;
  options.up_axis = 2;
  const SubjectLabelling result = LabelSubject(gapped, set, options);
  const auto [right, wrong] = RightAndWrong(result, motion);
  EXPECT_EQ(wrong, 0u);
  EXPECT_GE(static_cast<double>(right), 0.99 * static_cast<double>(result.points));
  // The last quarter is named as well as the first.
  size_t late_right = 0, late_points = 0;
  for (size_t f = 3000; f < 4000; ++f)
    for (size_t c = 0; c < result.named.NumMarkers(); ++c) {
      if (!result.named.Has(f, c)) continue;
      ++late_points;
      const int m = set.Find(result.named.names[c]);
      late_right += m >= 0 && (result.named.At(f, c) - motion.At(f, static_cast<size_t>(m))).norm() < 1e-6;
    }
  EXPECT_GE(static_cast<double>(late_right), 0.99 * static_cast<double>(late_points));
  EXPECT_GE(result.init_names, 10u);
  EXPECT_FALSE(result.decisions.empty());
}

TEST(SubjectLabeller, AnotherSubjectOfOtherProportionsIsInitialisedByItself) {
  // Taller and narrower (z 1.12 times, x and y 0.92 times about the body's centre), with gaps: the
  // set's distances are not this subject's, its own are learned once initialised.
  const MarkerTrajectories motion = Motion(1200, 0);
  MarkerTrajectories first = motion;
  first.frame_numbers.resize(300);
  first.points.resize(300 * motion.NumMarkers());
  const MarkerSet set = LearnMarkerSet({first}, {"first frames"});
  MarkerTrajectories other = motion;
  for (size_t f = 0; f < other.NumFrames(); ++f) {
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (size_t m = 0; m < other.NumMarkers(); ++m) centre += motion.At(f, m) / static_cast<double>(other.NumMarkers());
    for (size_t m = 0; m < other.NumMarkers(); ++m)
      other.At(f, m) = centre + Eigen::Vector3d(0.92, 0.92, 1.12).asDiagonal() * (motion.At(f, m) - centre);
  }
  std::vector<size_t> truth;
  const MarkerTrajectories gapped = WithGaps(other, 200, 3, &truth);
  SubjectLabellerOptions options;
  options.up_axis = 2;
  const SubjectLabelling result = LabelSubject(gapped, set, options);
  const auto [right, wrong] = RightAndWrong(result, other);
  EXPECT_EQ(wrong, 0u);
  EXPECT_GE(static_cast<double>(right), 0.98 * static_cast<double>(result.points));
}

// A marker the cameras never see (as running.trc's L.Bicep): the set is never seen whole, but
// nearly; the subject is initialised from those frames and the hidden name stays unplaced. With
// no marker allowed missing nothing is initialised (the option is what makes the difference).
TEST(SubjectLabeller, AMarkerNeverSeenDoesNotStopTheInitialisation) {
  const MarkerTrajectories motion = Motion(300, 0);
  const MarkerSet set = LearnMarkerSet({motion}, {"whole"});
  std::vector<size_t> order;
  MarkerTrajectories anonymous = Anonymous(motion, 0, 300, &order);
  const size_t hidden = static_cast<size_t>(std::find(order.begin(), order.end(), 3) - order.begin());
  for (size_t f = 0; f < anonymous.NumFrames(); ++f) anonymous.At(f, hidden) = Eigen::Vector3d::Constant(std::nan(""));
  SubjectLabellerOptions options;
  options.up_axis = 2;
  const SubjectLabelling result = LabelSubject(anonymous, set, options);
  EXPECT_GE(result.init_names, 10u);
  EXPECT_EQ(std::count(result.named.names.begin(), result.named.names.end(), motion.names[3]), 0);
  const auto [right, wrong] = RightAndWrong(result, motion);
  EXPECT_EQ(wrong, 0u);
  EXPECT_GE(static_cast<double>(right), 0.9 * static_cast<double>(result.points));
  options.init_missing_share = 0.0;
  const SubjectLabelling strict = LabelSubject(anonymous, set, options);
  EXPECT_EQ(strict.init_names, 0u);
  EXPECT_EQ(strict.named_points, 0u);
}

TEST(SubjectLabeller, RefusesBadOptions) {
  const MarkerSet set = LearnMarkerSet({Motion(50, 0)}, {"m"});
  const std::vector<std::pair<std::string, void (*)(SubjectLabellerOptions*)>> cases = {
      {"break_frames", [](SubjectLabellerOptions* o) { o->break_frames = 0; }},
      {"init_missing_share", [](SubjectLabellerOptions* o) { o->init_missing_share = 0.6; }},
      {"init_agreement", [](SubjectLabellerOptions* o) { o->init_agreement = 0.5; }},
  };
  for (const auto& [field, spoil] : cases) {
    SubjectLabellerOptions bad;
    spoil(&bad);
    try {
      LabelSubject(Motion(50, 0), set, bad);
      ADD_FAILURE() << "accepted a bad " << field;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace mocap
