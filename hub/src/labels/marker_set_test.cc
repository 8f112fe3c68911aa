// Marker-set learning and its JSON: what is learned from a known motion, the round trip, and the
// reader's refusals.
#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "labels/marker_set.h"
#include "labels/marker_set_learning.h"
#include "simcore/synthetic_motion.h"

namespace mocap {
namespace {

MarkerTrajectories Named(MarkerTrajectories motion) {
  for (size_t m = 0; m < motion.names.size(); ++m) motion.names[m] = "S" + std::to_string(m + 1);
  return motion;
}

// Two rigid triangles (A, B: 3 markers each, fixed shapes) and a loose marker C moving freely.
MarkerTrajectories TwoTriangles() {
  MarkerTrajectories t;
  t.rate_hz = 100.0;
  t.names = {"A1", "A2", "A3", "B1", "B2", "B3", "C"};
  for (int f = 0; f < 50; ++f) {
    const size_t i = t.AddFrame(static_cast<uint64_t>(f));
    const double s = 0.05 * f;
    const Eigen::Vector3d a(100.0 * s, 0.0, 1000.0), b(0.0, 300.0 + 50.0 * s, 500.0);
    t.At(i, 0) = a, t.At(i, 1) = a + Eigen::Vector3d(80, 0, 0), t.At(i, 2) = a + Eigen::Vector3d(0, 60, 20);
    t.At(i, 3) = b, t.At(i, 4) = b + Eigen::Vector3d(0, 0, 90), t.At(i, 5) = b + Eigen::Vector3d(40, 70, 0);
    t.At(i, 6) = Eigen::Vector3d(300.0 * std::sin(s), 200.0 * std::cos(3 * s), 800.0 + 100.0 * s);
  }
  return t;
}

TEST(MarkerSetLearning, FindsRigidSegmentsAndDistances) {
  const MarkerSet set = LearnMarkerSet({TwoTriangles()}, {"triangles"});
  ASSERT_EQ(set.names.size(), 7u);
  ASSERT_EQ(set.segments.size(), 2u);
  EXPECT_EQ(set.segments[0], (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(set.segments[1], (std::vector<int>{3, 4, 5}));
  EXPECT_EQ(set.SegmentOf(6), -1);
  const MarkerDistance* d = set.Distance(1, 0);
  ASSERT_NE(d, nullptr);
  EXPECT_NEAR(d->mean, 80.0, 1e-9);
  EXPECT_NEAR(d->sd, 0.0, 1e-6);
  EXPECT_EQ(d->frames, 50u);
  const MarkerDistance* loose = set.Distance(0, 6);
  ASSERT_NE(loose, nullptr);
  EXPECT_GT(loose->sd, 5.0);
  EXPECT_LT(loose->min, loose->max);
  // The mean shape keeps the rigid triangle's sides, centred, z up (the trial is z-up).
  EXPECT_NEAR((set.mean_shape[0] - set.mean_shape[1]).norm(), 80.0, 1.0);
}

TEST(MarkerSetLearning, RefusesAnonymousTrials) {
  SyntheticMotionOptions options;
  options.markers = 12;
  const MarkerTrajectories anonymous = MakeSyntheticMotion(options);  // M001...
  EXPECT_THROW(LearnMarkerSet({anonymous}, {"anon"}), std::invalid_argument);
  EXPECT_NO_THROW(LearnMarkerSet({Named(anonymous)}, {"named"}));
  EXPECT_THROW(LearnMarkerSet({}, {}), std::invalid_argument);
}

TEST(MarkerSetJson, RoundTrips) {
  const MarkerSet set = LearnMarkerSet({TwoTriangles()}, {"triangles"});
  const MarkerSet again = MarkerSetFromJson(nlohmann::json::parse(MarkerSetToJson(set).dump()), "again");
  EXPECT_EQ(again.names, set.names);
  EXPECT_EQ(again.segments, set.segments);
  ASSERT_EQ(again.distances.size(), set.distances.size());
  for (size_t i = 0; i < set.distances.size(); ++i) EXPECT_DOUBLE_EQ(again.distances[i].mean, set.distances[i].mean);
  for (size_t m = 0; m < set.names.size(); ++m) EXPECT_TRUE(again.mean_shape[m].isApprox(set.mean_shape[m]));
}

TEST(MarkerSetJson, RefusesBadFilesWithAReason) {
  auto reason = [](const std::string& text) {
    try {
      MarkerSetFromJson(nlohmann::json::parse(text), "set.json");
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const std::string head = R"({"version": 1, "type": "marker-set", )";
  EXPECT_NE(reason(R"({"version": 2, "type": "marker-set", "markers": [{"name": "a"}]})").find("not a marker set"), std::string::npos);
  EXPECT_NE(reason(R"({"version": 1, "type": ["marker-set"], "markers": [{"name": "a"}]})").find("not a marker set"), std::string::npos);
  EXPECT_NE(reason(head + R"("markers": []})").find("non-empty"), std::string::npos);
  EXPECT_NE(reason(head + R"("markers": [{"name": "a"}, {"name": "a"}]})").find("twice"), std::string::npos);
  EXPECT_NE(reason(head + R"("markers": [{"name": "a", "mean": [1, 2]}]})").find("mean"), std::string::npos);
  EXPECT_NE(reason(head + R"("markers": [{"name": "a"}, {"name": "b"}], "segments": [["a", "c"]]})").find("unknown marker 'c'"),
            std::string::npos);
  EXPECT_NE(reason(head + R"("markers": [{"name": "a"}, {"name": "b"}, {"name": "c"}], "segments": [["a", "b"], ["b", "c"]]})")
                .find("two segments"),
            std::string::npos);
  EXPECT_NE(reason(head + R"("markers": [{"name": "a"}, {"name": "b"}], "distances": [{"a": "a", "b": "b", "mean": 5, "sd": 1, "min": 6, "max": 9, "frames": 3}]})")
                .find("min <= mean <= max"),
            std::string::npos);
  EXPECT_NE(reason(head + R"("markers": [{"name": "a"}, {"name": "b"}], "distances": [{"a": "a", "b": "a", "mean": 5, "sd": 1, "min": 4, "max": 9, "frames": 3}]})")
                .find("itself"),
            std::string::npos);
  EXPECT_EQ(reason(head + R"("markers": [{"name": "a", "mean": null}, {"name": "b", "mean": [0, 0, 1]}]})"), "accepted");
}

}  // namespace
}  // namespace mocap
