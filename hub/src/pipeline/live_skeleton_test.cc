// The live skeleton stage on frames built from a simulated subject (no sockets): points named by a
// marker set whose order is not the skeleton's and that names markers the skeleton lacks, in a
// z-up (or upside-down) world; the bones come back where the true pose puts them, the residuals
// are the fit's; frames with too few named markers carry no bones and say so, the next full frame
// is solved again; a marker set that names too few of the skeleton's markers is refused.
#include "pipeline/live_skeleton.h"

#include <algorithm>
#include <random>

#include <gtest/gtest.h>

#include "skeleton/kinematics.h"
#include "skeleton/skeleton_sim.h"
#include "skeleton/skeleton_testing.h"

namespace mocap::pipeline {
namespace {

SkeletonSimulation Gait() {
  SkeletonSimOptions options;
  options.motion = SkeletonSimMotion::kGait;
  options.duration_s = 0.5;
  options.wobble_mm = 0.0;
  return SimulateSkeleton(TwentySegmentTemplate(), options);
}

// The marker set: the skeleton's names shuffled, with two it does not have.
std::vector<std::string> MarkerSetNames(const Skeleton& skeleton) {
  std::vector<std::string> names = {"EXTRA1"};
  for (const SkeletonMarker& m : skeleton.markers) names.push_back(m.name);
  names.push_back("EXTRA2");
  std::shuffle(names.begin(), names.end(), std::mt19937(3));
  return names;
}

// Frame f's named points in a world whose up axis is `up_axis`, plus one unnamed stray point; the
// markers of `hidden` segments left out.
LiveFrame FrameOf(const SkeletonSimulation& sim, const std::vector<std::string>& names, size_t f, int up_axis,
                  size_t keep = 1000) {
  const Eigen::Matrix3d world = WorldFromSkeletonUp(up_axis);
  LiveFrame frame;
  frame.frame_number = f;
  for (size_t l = 0; l < names.size() && frame.points.size() < keep; ++l) {
    const int m = sim.subject.FindMarker(names[l]);
    if (m < 0) continue;
    LivePoint p;
    p.position = world * sim.markers.At(f, static_cast<size_t>(m));
    p.label = static_cast<int>(l);
    frame.points.push_back(p);
  }
  LivePoint stray;
  stray.position = Eigen::Vector3d(5000, 5000, 5000);
  frame.points.push_back(stray);
  return frame;
}

double AngleDeg(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return a.angularDistance(b) * 180.0 / M_PI;
}

void ExpectTruePose(const SkeletonSimulation& sim, int up_axis) {
  const std::vector<std::string> names = MarkerSetNames(sim.subject);
  LiveSkeletonOptions options;
  options.name = "subject";
  options.up_axis = up_axis;
  LiveSkeletonStage stage(sim.subject, names, options);
  EXPECT_EQ(stage.named_markers(), sim.subject.markers.size());
  const Eigen::Matrix3d world = WorldFromSkeletonUp(up_axis);
  SkeletonPoseState truth;
  for (size_t f = 0; f < sim.markers.NumFrames(); ++f) {
    LiveFrame frame = FrameOf(sim, names, f, up_axis);
    stage.Run(&frame);
    ASSERT_EQ(frame.skeletons.size(), 1u);
    const LiveSkeleton& s = frame.skeletons[0];
    ASSERT_TRUE(s.solved) << f;
    EXPECT_STREQ(s.state, "solved");
    EXPECT_EQ(s.markers, static_cast<int>(sim.subject.markers.size()));
    EXPECT_LT(s.rms_mm, 0.05) << f;
    EXPECT_GE(s.max_mm, s.rms_mm);
    ASSERT_EQ(s.model->bones.size(), sim.subject.segments.size());
    EXPECT_EQ(s.model->name, "subject");
    EXPECT_EQ(s.model->bones[0], sim.subject.segments[0].name);
    EXPECT_EQ(s.model->parents[1], sim.subject.segments[1].parent);
    EXPECT_TRUE(s.model->offsets[1].isApprox(sim.subject.segments[1].offset));
    ForwardKinematics(sim.subject, sim.motion.poses[f].data(), nullptr, &truth);
    ASSERT_EQ(s.bones.size(), sim.subject.segments.size());
    for (size_t b = 0; b < s.bones.size(); ++b) {
      EXPECT_LT((s.bones[b].position - world * truth.origin[b]).norm(), 0.1) << f << " " << s.model->bones[b];
      EXPECT_LT(AngleDeg(s.bones[b].orientation, Eigen::Quaterniond(world * truth.rotation[b])), 0.1)
          << f << " " << s.model->bones[b];
    }
  }
}

TEST(LiveSkeleton, BonesFollowTheTruePoseInAZUpWorld) { ExpectTruePose(Gait(), 2); }

TEST(LiveSkeleton, BonesFollowTheTruePoseUpsideDown) { ExpectTruePose(Gait(), -2); }

TEST(LiveSkeleton, TooFewMarkersCarryNoBonesAndTheNextFullFrameIsSolved) {
  const SkeletonSimulation sim = Gait();
  const std::vector<std::string> names = MarkerSetNames(sim.subject);
  LiveSkeletonOptions options;
  LiveSkeletonStage stage(sim.subject, names, options);
  LiveFrame first = FrameOf(sim, names, 0, 2);
  stage.Run(&first);
  ASSERT_TRUE(first.skeletons[0].solved);
  LiveFrame sparse = FrameOf(sim, names, 1, 2, 3);  // 3 named markers: below the minimum of 4
  stage.Run(&sparse);
  EXPECT_FALSE(sparse.skeletons[0].solved);
  EXPECT_STREQ(sparse.skeletons[0].state, "too few markers");
  EXPECT_EQ(sparse.skeletons[0].markers, 3);
  EXPECT_TRUE(sparse.skeletons[0].bones.empty());  // no stale pose
  EXPECT_EQ(sparse.skeletons[0].rms_mm, 0.0);
  LiveFrame full = FrameOf(sim, names, 2, 2);
  stage.Run(&full);
  ASSERT_TRUE(full.skeletons[0].solved);
  EXPECT_LT(full.skeletons[0].rms_mm, 0.05);
}

TEST(LiveSkeleton, RefusesAMarkerSetNamingTooFewOfItsMarkers) {
  const SkeletonSimulation sim = Gait();
  const std::vector<std::string> names = {"LFHD", "RFHD", "LBHD", "OTHER"};
  EXPECT_THROW(LiveSkeletonStage(sim.subject, names, LiveSkeletonOptions{}), std::invalid_argument);
  LiveSkeletonOptions bad;
  bad.up_axis = 3;
  EXPECT_THROW(LiveSkeletonStage(sim.subject, MarkerSetNames(sim.subject), bad), std::invalid_argument);
}

}  // namespace
}  // namespace mocap::pipeline
