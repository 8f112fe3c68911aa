// Body definitions: centred frames, refusals with reasons, the ambiguity check, the bodies file.
#include "bodies/body_definition.h"

#include <cmath>
#include <fstream>
#include <limits>

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "util/temporary_directory_testing.h"

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

TEST(BodyDefinition, MarkersThatDoNotMoveAsOnePieceAreNoRigidBody) {
  // A triangle turning and moving, with 1 mm of noise: rigid. The same with its third marker on
  // a limb swinging 40 mm towards the others: not, and the pair is named.
  std::vector<std::vector<Eigen::Vector3d>> rigid, skin;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int f = 0; f < 200; ++f) {
    const Eigen::Matrix3d r = Eigen::AngleAxisd(0.01 * f, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    const Eigen::Vector3d t(2.0 * f, 0, 1000), noise(0.5 * std::sin(f), 0.5 * std::cos(3.0 * f), 0);
    const Eigen::Vector3d a = t + r * Eigen::Vector3d(0, 0, 0), b = t + r * Eigen::Vector3d(120, 0, 0) + noise;
    rigid.push_back({a, b, t + r * Eigen::Vector3d(0, 90, 0)});
    skin.push_back({a, b, t + r * Eigen::Vector3d(0, 90 - 40.0 * (0.5 + 0.5 * std::sin(0.1 * f)), 0)});
  }
  rigid[7][2] = Eigen::Vector3d::Constant(nan);  // a marker not seen in a frame is left out
  const std::vector<std::string> names = {"A", "B", "C"};
  EXPECT_EQ(RigidityProblem(rigid, names), "");
  const std::string problem = RigidityProblem(skin, names);
  EXPECT_NE(problem.find("not rigid"), std::string::npos) << problem;
  EXPECT_NE(problem.find("between A and C"), std::string::npos) << problem;  // A-C changes most
  BodyDefinitionOptions loose;
  loose.rigidity_tolerance_mm = 100.0;
  EXPECT_EQ(RigidityProblem(skin, names, loose), "");
  loose.rigidity_tolerance_mm = 0.0;
  EXPECT_THROW(RigidityProblem(skin, names, loose), std::invalid_argument);
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
  const testing::TemporaryDirectory temp("body_definition_test");
  const std::string path = temp.File("bodies.json");
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
  // Two bodies of one name: the second was kept and the first dropped without a word.
  const std::string wand = "{\"name\": \"w\", \"markers\": [[0,0,0],[100,0,0],[0,60,0],[0,0,40]]}";
  EXPECT_NE(write("{\"version\": 1, \"bodies\": [" + wand + ", " + wand + "]}").find("body 2: the name 'w' is body 1's"),
            std::string::npos);
}

// A 4 x 4 x 4 grid of markers `spacing` mm apart.
std::vector<Eigen::Vector3d> Grid(double spacing) {
  std::vector<Eigen::Vector3d> markers;
  for (int x = 0; x < 4; ++x)
    for (int y = 0; y < 4; ++y)
      for (int z = 0; z < 4; ++z) markers.emplace_back(spacing * x, spacing * y, spacing * z);
  return markers;
}

// The file allows 64 markers a body. The ambiguity check compared every 4 of one body's markers
// with every 4 of the other's in every order (two 64-marker bodies: about 10^13 comparisons), so
// a file of two such bodies never finished loading (the bodies-file fuzzer: two bodies of 20
// markers took over a minute). Now it loads, and an ambiguity among them is still found.
TEST(BodyDefinition, BodiesOfManyMarkersLoadAndAreStillCheckedForAmbiguity) {
  nlohmann::json file = {{"version", 1}, {"bodies", nlohmann::json::array()}};
  auto add = [&](const std::string& name, const std::vector<Eigen::Vector3d>& markers) {
    nlohmann::json list = nlohmann::json::array();
    for (const Eigen::Vector3d& m : markers) list.push_back({m.x(), m.y(), m.z()});
    file["bodies"].push_back({{"name", name}, {"markers", list}});
  };
  add("small", Grid(15.0));
  add("large", Grid(150.0));
  const std::vector<RigidBodyDefinition> bodies = BodiesFromJson(file, "grids.json");
  ASSERT_EQ(bodies.size(), 2u);
  EXPECT_EQ(bodies[1].markers.size(), 64u);
  std::vector<Eigen::Vector3d> shares = Grid(150.0);
  shares.resize(60);  // four of the large grid's markers, at the same distances, among others
  for (size_t i = 0; i < shares.size(); ++i) shares[i] = shares[i] * 1.3 + Eigen::Vector3d(0, 0, 7.0 * (i % 5));
  const std::vector<Eigen::Vector3d> large = Grid(150.0);
  for (size_t i = 0; i < 4; ++i) shares[i] = large[i * 5] + Eigen::Vector3d(2000, 0, 0);
  add("twin", shares);
  try {
    BodiesFromJson(file, "grids.json");
    FAIL() << "accepted a body sharing four markers with another";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("grids.json: ambiguous rigid body: 'twin' and 'large' share 4 markers"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace mocap
