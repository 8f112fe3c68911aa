// Tests of the eval metrics on small hand-made cases whose answers are known.
#include "scoring/marker_accuracy.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace mocap {
namespace {

// Truth: `markers` markers 100 mm apart on x, moving 1 mm per frame on y.
MarkerTrajectories Truth(size_t markers, size_t frames) {
  MarkerTrajectories truth;
  truth.rate_hz = 100.0;
  for (size_t m = 0; m < markers; ++m) truth.names.push_back(DefaultMarkerName(m));
  for (size_t f = 0; f < frames; ++f) {
    truth.AddFrame(f);
    for (size_t m = 0; m < markers; ++m) truth.At(f, m) = Eigen::Vector3d(100.0 * m, 1.0 * f, 1000.0);
  }
  return truth;
}

TEST(MarkerAccuracyTest, PerfectResult) {
  const MarkerTrajectories truth = Truth(3, 10);
  const MarkerEvalReport report = EvaluateMarkers(truth, truth, nullptr);
  EXPECT_EQ(report.frames, 10u);
  EXPECT_EQ(report.matched, 30u);
  EXPECT_EQ(report.rmse_mm, 0.0);
  EXPECT_EQ(report.ghosts, 0u);
  EXPECT_EQ(report.missing, 0u);
  EXPECT_EQ(report.trajectories, 3u);
  EXPECT_EQ(report.fragmentation, 1.0);
  EXPECT_EQ(report.swaps, 0u);
}

TEST(MarkerAccuracyTest, NothingMatchedHasNoErrorFigure) {
  const MarkerTrajectories truth = Truth(2, 5);
  MarkerTrajectories far = truth;
  for (size_t f = 0; f < 5; ++f)
    for (size_t m = 0; m < 2; ++m) far.At(f, m) += Eigen::Vector3d(0, 0, 500.0);  // beyond any gate
  const MarkerEvalReport report = EvaluateMarkers(truth, far, nullptr);
  EXPECT_EQ(report.matched, 0u);
  const std::string text = report.ToText();
  EXPECT_NE(text.find("rmse_mm           n/a"), std::string::npos) << text;  // not 0.0000
  EXPECT_NE(EvaluateMarkers(truth, truth, nullptr).ToText().find("rmse_mm           0.0000"), std::string::npos);
}

TEST(MarkerAccuracyTest, ErrorsGhostsAndMissing) {
  const MarkerTrajectories truth = Truth(2, 20);
  MarkerTrajectories result = truth;
  result.names.push_back("ghost");
  result.points.clear();
  result.frame_numbers.clear();
  for (size_t f = 0; f < 20; ++f) {
    result.AddFrame(f);
    // Marker 0 off by 1 mm (3 mm on the last frame), marker 1 off by 25 mm (beyond the gate) on
    // frame 5 only, and a ghost on even frames.
    result.At(f, 0) = truth.At(f, 0) + Eigen::Vector3d(0, 0, f == 19 ? 3.0 : 1.0);
    result.At(f, 1) = truth.At(f, 1) + Eigen::Vector3d(f == 5 ? 25.0 : 0.0, 0, 0);
    if (f % 2 == 0) result.At(f, 2) = Eigen::Vector3d(5000, 0, 0);
  }
  const MarkerEvalReport report = EvaluateMarkers(truth, result, nullptr);
  EXPECT_EQ(report.matched, 39u);
  EXPECT_EQ(report.ghosts, 10u + 1u);
  EXPECT_DOUBLE_EQ(report.ghosts_per_frame, 11.0 / 20.0);
  EXPECT_EQ(report.missing, 1u);
  EXPECT_DOUBLE_EQ(report.missing_per_frame, 1.0 / 20.0);
  EXPECT_NEAR(report.rmse_mm, std::sqrt((19.0 * 1.0 + 9.0) / 39.0), 1e-12);
  EXPECT_NEAR(report.max_error_mm, 3.0, 1e-12);
  EXPECT_NEAR(report.p95_error_mm, 1.0, 1e-12);
  EXPECT_EQ(report.trajectories, 3u);
  EXPECT_DOUBLE_EQ(report.fragmentation, 1.5);
}

TEST(MarkerAccuracyTest, MatchingIsGloballyOptimal) {
  // Truth A at x=0, B at x=10; output points at x=4 and x=-12. Nearest-first would pair 4 with A
  // (4 mm) and leave -12 to B (22 mm, beyond the gate: a ghost and a missing marker); the optimal
  // matching pairs 4 with B (6 mm) and -12 with A (12 mm).
  MarkerTrajectories truth;
  truth.rate_hz = 10;
  truth.names = {"A", "B"};
  truth.AddFrame(0);
  truth.At(0, 0) = Eigen::Vector3d(0, 0, 0.5);
  truth.At(0, 1) = Eigen::Vector3d(10, 0, 0.5);
  MarkerTrajectories result;
  result.rate_hz = 10;
  result.names = {"P", "Q"};
  result.AddFrame(0);
  result.At(0, 0) = Eigen::Vector3d(4, 0, 0.5);
  result.At(0, 1) = Eigen::Vector3d(-12, 0, 0.5);
  const MarkerEvalReport report = EvaluateMarkers(truth, result, nullptr);
  EXPECT_EQ(report.matched, 2u);
  EXPECT_EQ(report.ghosts, 0u);
  EXPECT_EQ(report.missing, 0u);
  EXPECT_NEAR(report.rmse_mm, std::sqrt((36.0 + 144.0) / 2.0), 1e-12);
}

TEST(MarkerAccuracyTest, SwapsAndFragmentation) {
  const MarkerTrajectories truth = Truth(2, 10);
  MarkerTrajectories result;
  result.rate_hz = 100;
  result.names = {"a", "b", "c"};
  for (size_t f = 0; f < 10; ++f) {
    result.AddFrame(f);
    // Column a follows marker 0, then marker 1 from frame 6 (one swap); marker 0 continues in
    // column c from frame 6 (a new fragment); column b follows marker 1 until frame 5.
    if (f < 6) {
      result.At(f, 0) = truth.At(f, 0);
      result.At(f, 1) = truth.At(f, 1);
    } else {
      result.At(f, 0) = truth.At(f, 1);
      result.At(f, 2) = truth.At(f, 0);
    }
  }
  const MarkerEvalReport report = EvaluateMarkers(truth, result, nullptr);
  EXPECT_EQ(report.swaps, 1u);
  // Marker 0 moves from column a to c, marker 1 from b to a: one change of track each.
  EXPECT_EQ(report.id_changes, 2u);
  EXPECT_EQ(report.max_id_changes, 1u);
  EXPECT_DOUBLE_EQ(report.id_changes_per_marker, 1.0);
  EXPECT_EQ(report.name_changes, 0u);
  EXPECT_EQ(report.trajectories, 3u);
  EXPECT_DOUBLE_EQ(report.fragmentation, 1.5);
  EXPECT_EQ(report.missing, 0u);
  EXPECT_EQ(report.ghosts, 0u);
}

// Two markers 30 mm apart on a fast curve; `truth_traded` / `result_traded` say from which frame
// on the truth's labels / the result's columns have the two exchanged (-1: never).
MarkerEvalReport EvaluateExchange(long truth_traded, long result_traded) {
  const auto at = [](size_t marker, size_t f) {
    const double t = static_cast<double>(f);
    return Eigen::Vector3d(30.0 * t + 0.5 * t * t, 30.0 * marker + 20.0 * std::sin(t / 5.0), 1000.0);
  };
  MarkerTrajectories truth, result;
  truth.rate_hz = result.rate_hz = 100.0;
  truth.names = {"m0", "m1"};
  result.names = {"a", "b"};
  for (size_t f = 0; f < 30; ++f) {
    truth.AddFrame(f);
    result.AddFrame(f);
    for (size_t m = 0; m < 2; ++m) {
      const bool truth_swapped = truth_traded >= 0 && static_cast<long>(f) >= truth_traded;
      const bool result_swapped = result_traded >= 0 && static_cast<long>(f) >= result_traded;
      truth.At(f, m) = at(truth_swapped ? 1 - m : m, f);
      result.At(f, m) = at(result_swapped ? 1 - m : m, f);
    }
  }
  return EvaluateMarkers(truth, result, nullptr);
}

TEST(MarkerAccuracyTest, SwapsWhereTheTruthExchangesMarkersAreReportedApart) {
  // The truth's labels trade at frame 12; the result follows the markers themselves.
  MarkerEvalReport report = EvaluateExchange(12, -1);
  EXPECT_EQ(report.swaps, 2u);
  EXPECT_EQ(report.truth_exchanges, 1u);
  EXPECT_EQ(report.swaps_at_truth_exchanges, 2u);
  EXPECT_NE(report.ToText().find("exchange places"), std::string::npos);
  // The truth is right and the result trades: real swaps.
  report = EvaluateExchange(-1, 12);
  EXPECT_EQ(report.swaps, 2u);
  EXPECT_EQ(report.truth_exchanges, 0u);
  EXPECT_EQ(report.swaps_at_truth_exchanges, 0u);
  // Both trade at the same frame: no swap.
  report = EvaluateExchange(12, 12);
  EXPECT_EQ(report.swaps, 0u);
  EXPECT_EQ(report.truth_exchanges, 1u);
}

TEST(MarkerAccuracyTest, VisibilityDecidesWhatIsMissing) {
  const MarkerTrajectories truth = Truth(2, 4);
  MarkerTrajectories result = truth;
  for (size_t f = 0; f < 4; ++f) result.At(f, 1) = MarkerTrajectories::Gap();
  MarkerVisibility visibility;
  visibility.names = truth.names;
  visibility.frame_numbers = {0, 1, 2, 3};
  // Marker 1 is seen by only one camera on frames 0-2, by three on frame 3.
  visibility.counts = {4, 1, 4, 1, 4, 1, 4, 3};
  EXPECT_EQ(EvaluateMarkers(truth, result, nullptr).missing, 4u);
  const MarkerEvalReport report = EvaluateMarkers(truth, result, &visibility);
  EXPECT_TRUE(report.visibility_used);
  EXPECT_EQ(report.missing, 1u);
  EXPECT_EQ(report.expected_points, 5u);
  visibility.names = {"x", "y"};
  EXPECT_THROW(EvaluateMarkers(truth, result, &visibility), std::invalid_argument);
}

TEST(MarkerAccuracyTest, FramesAlignByTime) {
  const MarkerTrajectories truth = Truth(1, 10);  // 100 Hz, frames 0..9
  MarkerTrajectories result;
  result.rate_hz = 200.0;
  result.names = {"r"};
  // At 200 Hz, frame 2k is truth frame k; odd frames have no truth instant; frames 4..7 of the
  // truth have no result row at all (missing).
  for (uint64_t k : {0, 1, 2, 3, 8, 9}) {
    const size_t f = result.AddFrame(2 * k);
    result.At(f, 0) = truth.At(k, 0);
  }
  const size_t odd = result.AddFrame(21);
  result.At(odd, 0) = Eigen::Vector3d(0, 0, 0);
  const MarkerEvalReport report = EvaluateMarkers(truth, result, nullptr);
  EXPECT_EQ(report.result_frames, 6u);
  EXPECT_EQ(report.unaligned_result_frames, 1u);
  EXPECT_EQ(report.matched, 6u);
  EXPECT_EQ(report.missing, 4u);
  EXPECT_EQ(report.rmse_mm, 0.0);
  EXPECT_EQ(report.ghosts, 0u);
}

TEST(MarkerAccuracyTest, AnonymousColumnsAreUnnamedNeverWrong) {
  // A synthetic truth calls its markers M001...; the result's columns, also M001..., follow other
  // markers (the hub's anonymous numbering). No column is named: nothing is wrong.
  const MarkerTrajectories truth = Truth(3, 5);
  MarkerTrajectories result = truth;
  for (size_t f = 0; f < 5; ++f) {
    for (size_t m = 0; m < 3; ++m) result.At(f, m) = truth.At(f, (m + 1) % 3);
  }
  MarkerEvalReport report = EvaluateMarkers(truth, result, nullptr);
  EXPECT_FALSE(report.labels_compared);
  EXPECT_EQ(report.wrongly_named, 0u);
  EXPECT_EQ(report.named_points, 0u);
  EXPECT_EQ(report.ToText().find("labels"), std::string::npos);
}

TEST(MarkerAccuracyTest, NamesAreRightWrongOrUnnamed) {
  MarkerTrajectories truth = Truth(3, 10);
  truth.names = {"A", "B", "C"};
  MarkerTrajectories result = truth;
  // Column A right, column "B" follows marker C (wrong), column M003 follows marker B (unnamed).
  result.names = {"A", "B", "M003"};
  for (size_t f = 0; f < 10; ++f) {
    result.At(f, 1) = truth.At(f, 2);
    result.At(f, 2) = truth.At(f, 1);
  }
  const MarkerEvalReport report = EvaluateMarkers(truth, result, nullptr);
  EXPECT_TRUE(report.labels_compared);
  EXPECT_EQ(report.label_points, 30u);
  EXPECT_EQ(report.correctly_named, 10u);
  EXPECT_EQ(report.wrongly_named, 10u);
  EXPECT_EQ(report.unnamed_points, 10u);
  EXPECT_DOUBLE_EQ(report.correct_share, 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(report.wrong_share, 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(report.unnamed_share, 1.0 / 3.0);
}

// A live result: one pool column holding marker A's points (marker B is not published),
// published by track 1 (frames 0-4) then track 3; names per point as given.
MarkerEvalReport EvaluateLive(const std::vector<int32_t>& names_of_frames, const MarkerEvalOptions& options = {}) {
  MarkerTrajectories truth = Truth(2, names_of_frames.size());
  truth.names = {"A", "B"};
  MarkerTrajectories result;
  result.rate_hz = truth.rate_hz;
  result.names = {"P1"};
  for (size_t f = 0; f < truth.NumFrames(); ++f) result.At(result.AddFrame(truth.frame_numbers[f]), 0) = truth.At(f, 0);
  PublishedIdentity identity;
  identity.names = {"A", "B", "M001"};
  for (size_t f = 0; f < names_of_frames.size(); ++f) {
    identity.track.push_back(f < 5 ? 1 : 3);
    identity.name.push_back(names_of_frames[f]);
  }
  return EvaluateMarkers(truth, result, nullptr, options, &identity);
}

TEST(MarkerAccuracyTest, LiveIdsAndNamesChangedPerTrack) {
  // Track 1: A, unnamed, A, B, B (one change; unnamed between does not count); track 3: M001
  // (anonymous: unnamed) then A.
  const MarkerEvalReport report = EvaluateLive({0, -1, 0, 1, 1, 2, 0, 0, 0, 0});
  EXPECT_EQ(report.id_changes, 1u);
  EXPECT_EQ(report.max_id_changes, 1u);
  EXPECT_EQ(report.trajectories, 2u);
  EXPECT_EQ(report.name_changes, 1u);
  EXPECT_EQ(report.tracks_renamed, 1u);
  EXPECT_EQ(report.max_name_changes, 1u);
  EXPECT_EQ(report.correctly_named, 6u);
  EXPECT_EQ(report.wrongly_named, 2u);
  EXPECT_EQ(report.unnamed_points, 2u);
  EXPECT_EQ(report.swaps, 0u);
  // A track renamed back and forth: every change counts.
  EXPECT_EQ(EvaluateLive({0, 1, 0, 1, 0, 0, 0, 0, 0, 0}).name_changes, 4u);
}

// A live_points.tsv as serve writes it: two markers published provisional for two frames, then
// confirmed. Its ids are scored as published: one id per track from its first frame (version 2)
// is no change; a version 1 file's new number on confirmation is one per marker.
MarkerEvalReport EvaluateLivePointsFile(const std::string& header, const long long provisional_ids[2],
                                        const long long confirmed_ids[2]) {
  MarkerTrajectories truth = Truth(2, 6);
  std::string text = header;
  for (size_t f = 0; f < truth.NumFrames(); ++f) {
    for (size_t m = 0; m < 2; ++m) {
      const Eigen::Vector3d p = truth.At(f, m);
      text += LivePointLine(truth.frame_numbers[f], p.x(), p.y(), p.z(), f < 2 ? provisional_ids[m] : confirmed_ids[m],
                            f < 2, 3, 0.1);
    }
  }
  std::istringstream in(text);
  const LivePoints live = ParseLivePoints(in, "live_points.tsv");
  return EvaluateMarkers(truth, live.points, nullptr, {}, &live.identity);
}

TEST(MarkerAccuracyTest, LivePointsFilesScoredAsPublished) {
  const long long ids[2] = {7, 9};
  const MarkerEvalReport kept = EvaluateLivePointsFile(LivePointsHeader(100), ids, ids);
  EXPECT_EQ(kept.id_changes, 0u);
  EXPECT_EQ(kept.trajectories, 2u);
  EXPECT_EQ(kept.matched, 12u);
  const long long markers[2] = {0, 1};
  const MarkerEvalReport renumbered =
      EvaluateLivePointsFile("# mocap live points v1 rate_hz=100\n", ids, markers);
  EXPECT_EQ(renumbered.id_changes, 2u);
  EXPECT_EQ(renumbered.max_id_changes, 1u);
  EXPECT_EQ(renumbered.trajectories, 4u);
}

TEST(MarkerAccuracyTest, NamesCountFromEachMarkersChosenFrame) {
  MarkerEvalOptions options;
  options.names_from_frame = 3;
  // Wrong on the marker's first two frames, right afterwards.
  const MarkerEvalReport report = EvaluateLive({1, 1, 0, 0, 0, 0, 0, 0, 0, 0}, options);
  EXPECT_EQ(report.label_points, 8u);
  EXPECT_EQ(report.wrongly_named, 0u);
  EXPECT_EQ(report.missing, 10u);  // marker B, never published
  EXPECT_DOUBLE_EQ(report.correct_share, 1.0);
  EXPECT_EQ(report.result_points, 10u);
  EXPECT_EQ(EvaluateLive({1, 1, 0, 0, 0, 0, 0, 0, 0, 0}).wrongly_named, 2u);
  options.names_from_frame = 0;
  EXPECT_THROW(options.Check(), std::invalid_argument);
}

TEST(MarkerAccuracyTest, IdentityMustCoverTheResult) {
  const MarkerTrajectories truth = Truth(2, 3);
  PublishedIdentity identity;
  identity.track.assign(5, 0);
  identity.name.assign(5, -1);
  EXPECT_THROW(EvaluateMarkers(truth, truth, nullptr, {}, &identity), std::invalid_argument);
}

TEST(MarkerAccuracyTest, JsonHasTheDesignNames) {
  const MarkerTrajectories truth = Truth(2, 3);
  const nlohmann::json json = EvaluateMarkers(truth, truth, nullptr).ToJson();
  for (const char* key : {"rmse_mm", "ghosts_per_frame", "missing_per_frame", "trajectories", "fragmentation",
                          "swaps", "max_error_mm", "p95_error_mm", "id_changes", "name_changes",
                          "unnamed_share"}) {
    EXPECT_TRUE(json.contains(key)) << key;
  }
  EXPECT_EQ(json["trajectories"], 2);
  EXPECT_FALSE(EvaluateMarkers(truth, truth, nullptr).ToText().empty());
}

}  // namespace
}  // namespace mocap
