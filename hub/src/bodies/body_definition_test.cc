// Body definitions: centred frames, refusals with reasons, the ambiguity check, the bodies file.
#include "bodies/body_definition.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

namespace mocap {
namespace {

std::vector<Eigen::Vector3d> Shift(std::vector<Eigen::Vector3d> v, const Eigen::Vector3d& by) {
  for (auto& p : v) p += by;
  return v;
}

const std::vector<Eigen::Vector3d> kWand = {{0, 0, 0}, {120, 0, 0}, {0, 80, 0}, {40, 30, 50}};

TEST(BodyDefinition, CentredAndChecked) {
  const RigidBodyDefinition b = DefineBody("wand", Shift(kWand, {1000, 2000, 500}));
  ASSERT_EQ(b.markers.size(), 4u);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& m : b.markers) sum += m;
  EXPECT_LT(sum.norm(), 1e-9);
  EXPECT_NEAR((b.markers[1] - b.markers[0]).norm(), 120.0, 1e-9);
  EXPECT_EQ(b.pivot, Eigen::Vector3d::Zero());
  EXPECT_THROW(DefineBody("two", {{0, 0, 0}, {100, 0, 0}}), std::invalid_argument);
  EXPECT_THROW(DefineBody("line", {{0, 0, 0}, {100, 0, 0}, {200, 0, 0}}), std::invalid_argument);
  try {
    DefineBody("close", {{0, 0, 0}, {5, 0, 0}, {0, 100, 0}});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("5.0 mm apart"), std::string::npos) << e.what();
  }
  EXPECT_THROW(DefineBody("", kWand), std::invalid_argument);
}

TEST(BodyDefinition, AmbiguousBodiesAreRefusedWithTheirDistances) {
  std::vector<RigidBodyDefinition> bodies;
  AddBody(bodies, DefineBody("wand", kWand));
  // The wand's four markers and a fifth: when those four are seen it could be either.
  const auto twin = DefineBody("twin", {{0, 0, 0}, {120, 0, 0}, {0, 80, 0}, {40, 30, 50}, {-60, -40, 90}});
  try {
    AddBody(bodies, twin);
    FAIL();
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("'twin' and 'wand'"), std::string::npos) << what;
    EXPECT_NE(what.find("120.0"), std::string::npos) << what;
    EXPECT_NE(what.find("80.0"), std::string::npos) << what;
  }
  EXPECT_EQ(bodies.size(), 1u);
  // Sharing a triangle only is fine: the tracker starts from four markers.
  AddBody(bodies, DefineBody("cousin", {{0, 0, 0}, {120, 0, 0}, {0, 80, 0}, {-60, -40, 90}}));
  // A different shape goes in; redefining a body by its name replaces it.
  AddBody(bodies, DefineBody("drone", {{0, 0, 0}, {150, 0, 0}, {30, 110, 0}, {70, 40, -35}}));
  AddBody(bodies, DefineBody("wand", Shift(kWand, {5, 5, 5})));
  EXPECT_EQ(bodies.size(), 3u);
  EXPECT_TRUE(Ambiguity(bodies[0], bodies[2]).empty());
}

TEST(BodyDefinition, FileRoundTripAndBadFiles) {
  const std::string path =
      (std::filesystem::temp_directory_path() / ("mocap_bodies_" + std::to_string(::getpid()) + ".json")).string();
  std::vector<RigidBodyDefinition> bodies = {DefineBody("wand", kWand)};
  bodies[0].pivot = {0, 0, -100};
  WriteBodiesFile(bodies, path);
  const auto back = ReadBodiesFile(path);
  ASSERT_EQ(back.size(), 1u);
  EXPECT_EQ(back[0].name, "wand");
  EXPECT_LT((back[0].markers[3] - bodies[0].markers[3]).norm(), 1e-9);
  EXPECT_EQ(back[0].pivot, Eigen::Vector3d(0, 0, -100));
  auto write = [&](const std::string& text) {
    std::ofstream(path) << text;
    try {
      ReadBodiesFile(path);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(write("{\"version\": 2, \"bodies\": []}").find("not a bodies file"), std::string::npos);
  EXPECT_NE(write("{\"version\": \"1\", \"bodies\": []}").find("not a bodies file"), std::string::npos);
  EXPECT_NE(write("{\"version\": 1, \"bodies\": [{\"name\": \"a\"}]}").find("needs"), std::string::npos);
  EXPECT_NE(write("{\"version\": 1, \"bodies\": [{\"name\": \"a\", \"markers\": [[0,0,0],[1,2]]}]}").find("[x, y, z]"),
            std::string::npos);
  EXPECT_NE(write("{\"version\": 1, \"bodies\": [{\"name\": \"a\", \"markers\": [[0,0,0],[100,0,0]]}]}").find("at least 3"),
            std::string::npos);
  EXPECT_NE(write("not json").find(path), std::string::npos);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace mocap
