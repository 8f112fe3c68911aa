// Rigid-body pose accuracy: known errors come out as such, a swapped identity counts as gross,
// availability follows the visibility of the body's markers.
#include <stdexcept>

#include <gtest/gtest.h>

#include "eval/body_accuracy.h"

namespace mocap {
namespace {

BodyPoseRecord Record(uint64_t frame, const std::string& body, const Eigen::Vector3d& pivot, double angle_deg,
                      bool tracked = true) {
  BodyPoseRecord r;
  r.frame = frame;
  r.body = body;
  r.tracked = tracked;
  r.pivot = pivot;
  r.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(angle_deg * 3.14159265358979323846 / 180.0, Eigen::Vector3d::UnitZ()));
  return r;
}

TEST(BodyAccuracy, ErrorsGrossAndAvailability) {
  std::vector<BodyPoseRecord> truth, result;
  for (uint64_t f = 1; f <= 10; ++f) {
    truth.push_back(Record(f, "a", {0, 0, 0}, 0.0));
    truth.push_back(Record(f, "b", {500, 0, 0}, 30.0));
    // a: 0.4 mm and 0.2 deg off; fitted in 9 frames. b: right, but frame 5 carries a's pose (a swap).
    result.push_back(Record(f, "a", {0.4, 0, 0}, 0.2, f != 10));
    result.push_back(f == 5 ? Record(f, "b", {0, 0, 0}, 0.0) : Record(f, "b", {500, 0, 0}, 30.0));
  }
  MarkerVisibility visibility;
  visibility.names = {"S1", "a:1", "a:2", "a:3", "b:1", "b:2", "b:3"};
  for (uint64_t f = 0; f < 10; ++f) {
    visibility.frame_numbers.push_back(f);
    // a's third marker is seen by one camera only in frames 8-9 (file frames 9-10).
    for (int c : {4, 2, 2, f >= 8 ? 1 : 3, 2, 2, 2}) visibility.counts.push_back(static_cast<uint16_t>(c));
  }
  const BodyEvalReport report = EvaluateBodies(truth, result, &visibility);
  ASSERT_EQ(report.bodies.size(), 2u);
  const auto& a = report.bodies[0];
  EXPECT_EQ(a.name, "a");
  EXPECT_EQ(a.fitted, 9u);
  EXPECT_EQ(a.seen, 8u);
  EXPECT_EQ(a.fitted_when_seen, 8u);
  EXPECT_DOUBLE_EQ(a.available_share, 1.0);
  EXPECT_NEAR(a.p50_mm, 0.4, 1e-9);
  EXPECT_NEAR(a.p50_deg, 0.2, 1e-6);
  EXPECT_EQ(a.gross, 0u);
  const auto& b = report.bodies[1];
  EXPECT_EQ(b.gross, 1u);
  EXPECT_NEAR(b.p50_mm, 0.0, 1e-9);
  EXPECT_NEAR(b.max_mm, 500.0, 1e-9);
  const BodyEvalReport without = EvaluateBodies(truth, result, nullptr);
  EXPECT_EQ(without.bodies[0].seen, 10u);
  EXPECT_THROW(EvaluateBodies(truth, {result[0]}, nullptr), std::invalid_argument);
}

}  // namespace
}  // namespace mocap
