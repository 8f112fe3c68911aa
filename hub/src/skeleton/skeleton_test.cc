// The skeleton file: what is written reads back the same; malformed files are refused naming the
// field (each refusal below fails if its check is removed from the reader).
#include "skeleton/skeleton.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "skeleton/skeleton_template.h"

namespace mocap {
namespace {

Skeleton Hdm() {
  std::vector<std::string> unplaced;
  return SkeletonTemplateFromNames({"LFWT", "RFWT", "LBWT", "RBWT", "LTHI", "LKNE", "LSHN", "LANK", "LHEE", "LTOE"},
                                   &unplaced);
}

std::string Refusal(const nlohmann::json& document) {
  try {
    SkeletonFromJson(document, "t.json");
  } catch (const std::runtime_error& error) {
    return error.what();
  }
  return "";
}

TEST(SkeletonFile, RoundTrip) {
  Skeleton s = Hdm();
  s.markers[1].weight = 2.5;
  s.segments[2].end = Eigen::Vector3d(1, 2, 3);
  const Skeleton back = SkeletonFromJson(SkeletonToJson(s), "t");
  ASSERT_EQ(back.NumSegments(), s.NumSegments());
  ASSERT_EQ(back.markers.size(), s.markers.size());
  for (size_t g = 0; g < s.NumSegments(); ++g) {
    EXPECT_EQ(back.segments[g].name, s.segments[g].name);
    EXPECT_EQ(back.segments[g].parent, s.segments[g].parent);
    EXPECT_EQ(back.segments[g].bone, s.segments[g].bone);
    EXPECT_EQ(back.segments[g].reference_zero, s.segments[g].reference_zero);
    EXPECT_TRUE(back.segments[g].offset.isApprox(s.segments[g].offset));
    EXPECT_TRUE(back.segments[g].end.isApprox(s.segments[g].end));
    ASSERT_EQ(back.segments[g].dofs.size(), s.segments[g].dofs.size());
    for (size_t d = 0; d < s.segments[g].dofs.size(); ++d) {
      EXPECT_EQ(back.segments[g].dofs[d].axis, s.segments[g].dofs[d].axis);
      EXPECT_EQ(back.segments[g].dofs[d].min_deg, s.segments[g].dofs[d].min_deg);
    }
  }
  EXPECT_EQ(back.markers[1].weight, 2.5);
  EXPECT_EQ(back.markers[3].segment, s.markers[3].segment);
  EXPECT_EQ(back.NumPoseParameters(), s.NumPoseParameters());
}

TEST(SkeletonFile, RefusesWithReasons) {
  const nlohmann::json good = SkeletonToJson(Hdm());
  EXPECT_EQ(Refusal(good), "");
  nlohmann::json bad = good;
  bad["type"] = "marker-set";
  EXPECT_NE(Refusal(bad).find("type"), std::string::npos);
  bad = good;
  bad["segments"][1]["parent"] = "Nowhere";
  EXPECT_NE(Refusal(bad).find("not an earlier segment"), std::string::npos);
  bad = good;
  bad["segments"].push_back(bad["segments"].back());
  EXPECT_NE(Refusal(bad).find("name used twice"), std::string::npos);
  bad = good;
  bad["segments"][1]["dofs"][0]["axis"] = "w";
  EXPECT_NE(Refusal(bad).find("is not x, y or z"), std::string::npos);
  bad = good;
  bad["segments"][1]["dofs"][0]["min"] = 200;
  EXPECT_NE(Refusal(bad).find("limits"), std::string::npos);
  bad = good;
  bad["segments"][0]["dofs"].erase(0);
  EXPECT_NE(Refusal(bad).find("exactly 3"), std::string::npos);
  bad = good;
  bad["segments"][2]["offset"] = {0, 1e300, 0};
  EXPECT_NE(Refusal(bad).find("not finite"), std::string::npos);
  bad = good;
  bad["markers"][0]["segment"] = "Nowhere";
  EXPECT_NE(Refusal(bad).find("is not a segment"), std::string::npos);
  bad = good;
  bad["markers"][0]["weight"] = 0;
  EXPECT_NE(Refusal(bad).find("weight"), std::string::npos);
  bad = good;
  bad["markers"][1]["name"] = bad["markers"][0]["name"];
  EXPECT_NE(Refusal(bad).find("name used twice"), std::string::npos);
  bad = good;
  bad["segments"][0]["dofs"][1]["axis"] = bad["segments"][0]["dofs"][0]["axis"];
  EXPECT_NE(Refusal(bad).find("two successive"), std::string::npos);
}

}  // namespace
}  // namespace mocap
