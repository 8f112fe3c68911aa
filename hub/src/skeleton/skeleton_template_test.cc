// Templates by rules: the two marker-set families get the segments their markers cover, sides
// mirrored, unknown names reported, and a set without a pelvis refused.
#include "skeleton/skeleton_template.h"

#include <gtest/gtest.h>

namespace mocap {
namespace {

const std::vector<std::string> kHdm = {
    "LFHD", "RFHD", "LBHD", "RBHD", "C7",   "T10",  "CLAV", "STRN", "RBAC", "LSHO", "LUPA", "LELB", "LFRM", "LWRA",
    "LWRB", "LFIN", "RSHO", "RUPA", "RELB", "RFRM", "RWRA", "RWRB", "RFIN", "LFWT", "RFWT", "LBWT", "RBWT", "LTHI",
    "LKNE", "LSHN", "LANK", "LHEE", "LTOE", "LMT5", "RTHI", "RKNE", "RSHN", "RANK", "RHEE", "RTOE", "RMT5"};

TEST(SkeletonTemplate, Hdm05SetCoversTheWholeBody) {
  std::vector<std::string> unplaced;
  const Skeleton s = SkeletonTemplateFromNames(kHdm, &unplaced);
  EXPECT_TRUE(unplaced.empty());
  EXPECT_EQ(s.markers.size(), kHdm.size());
  // Hips, 2 x (UpLeg, Leg, Foot), Spine, Chest, Head, 2 x (Shoulder, Arm, ForeArm, Hand)
  EXPECT_EQ(s.NumSegments(), 18u);
  for (const char* name : {"Spine", "Chest", "Head", "RightHand", "LeftFoot", "RightShoulder"})
    EXPECT_GE(s.FindSegment(name), 0) << name;
  const int lk = s.FindMarker("LKNE"), rk = s.FindMarker("RKNE");
  EXPECT_EQ(s.segments[s.markers[lk].segment].name, "LeftUpLeg");
  EXPECT_EQ(s.segments[s.markers[rk].segment].name, "RightUpLeg");
  EXPECT_DOUBLE_EQ(s.markers[lk].offset.x(), -s.markers[rk].offset.x());
  // Mirrored limits: the left hip abducts to +z, the right to -z.
  const auto& left_hip = s.segments[s.FindSegment("LeftUpLeg")].dofs[1];
  const auto& right_hip = s.segments[s.FindSegment("RightUpLeg")].dofs[1];
  EXPECT_DOUBLE_EQ(left_hip.max_deg, -right_hip.min_deg);
  EXPECT_EQ(s.segments[s.FindSegment("Chest")].parent, s.FindSegment("Spine"));
}

TEST(SkeletonTemplate, OpenSimGaitSetHasNoHands) {
  const std::vector<std::string> names = {
      "R.ASIS", "L.ASIS", "V.Sacral", "R.Thigh.Upper", "R.Thigh.Front", "R.Thigh.Rear", "L.Thigh.Upper",
      "L.Thigh.Front", "L.Thigh.Rear", "R.Shank.Upper", "R.Shank.Front", "R.Shank.Rear", "L.Shank.Upper",
      "L.Shank.Front", "L.Shank.Rear", "R.Heel", "R.Midfoot.Sup", "R.Midfoot.Lat", "R.Toe.Tip", "L.Heel",
      "L.Midfoot.Sup", "L.Midfoot.Lat", "L.Toe.Tip", "Sternum", "R.Acromium", "L.Acromium", "R.Bicep", "L.Bicep",
      "R.Elbow", "L.Elbow", "R.Wrist.Med", "R.Wrist.Lat", "L.Wrist.Med", "L.Wrist.Lat", "R.Toe.Lat", "R.Toe.Med",
      "L.Toe.Lat", "L.Toe.Med", "R.Temple", "L.Temple", "Top.Head", "Racket"};
  std::vector<std::string> unplaced;
  const Skeleton s = SkeletonTemplateFromNames(names, &unplaced);
  EXPECT_EQ(unplaced, std::vector<std::string>{"Racket"});
  EXPECT_EQ(s.FindSegment("LeftHand"), -1);
  EXPECT_EQ(s.FindSegment("Spine"), -1);  // one trunk segment: only Chest markers
  EXPECT_GE(s.FindSegment("Chest"), 0);
  EXPECT_EQ(s.segments[s.FindSegment("Chest")].parent, 0);
  // Chest joins the pelvis where Spine's and Chest's offsets together reach.
  EXPECT_NEAR(s.segments[s.FindSegment("Chest")].offset.y(), 300.0, 1e-9);
  EXPECT_EQ(s.NumSegments(), 15u);
}

TEST(SkeletonTemplate, RefusesASetWithoutPelvis) {
  std::vector<std::string> unplaced;
  EXPECT_THROW(SkeletonTemplateFromNames({"LKNE", "LANK", "C7"}, &unplaced), std::invalid_argument);
}

}  // namespace
}  // namespace mocap
