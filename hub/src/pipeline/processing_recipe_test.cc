// Processing recipes: every field read and written back the same, the defaults of an almost
// empty recipe, and each refusal naming the field and the rule.
#include "pipeline/processing_recipe.h"

#include <stdexcept>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace mocap::pipeline {
namespace {

nlohmann::json Minimal() { return {{"format", "mocap-recipe"}, {"version", 1}}; }

std::string Refusal(const nlohmann::json& doc) {
  try {
    RecipeFromJson(doc, "r.json");
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "";
}

TEST(ProcessingRecipe, EveryFieldRoundTrips) {
  nlohmann::json doc = Minimal();
  doc.update({{"name", "gait-2"},      {"calibration", "rig.json"}, {"force_calibration", true}, {"matcher", "clustering"},
              {"assignment", "greedy"}, {"predictions", false},      {"hindsight_swaps", false},
              {"max_spline_gap_s", 0.2}, {"threads", 4},             {"labels", "set.json"},
              {"bodies", "b.json"},     {"bodies_window", 3},        {"bodies_degree", 1},
              {"outputs", {"c3d", "trc"}}});
  const ProcessingRecipe r = RecipeFromJson(doc, "r.json");
  EXPECT_EQ(r.name, "gait-2");
  EXPECT_EQ(r.calibration, "rig.json");
  EXPECT_TRUE(r.force_calibration);
  EXPECT_EQ(r.matcher, "clustering");
  EXPECT_EQ(r.assignment, "greedy");
  EXPECT_FALSE(r.predictions);
  EXPECT_FALSE(r.hindsight_swaps);
  EXPECT_DOUBLE_EQ(r.max_spline_gap_s, 0.2);
  EXPECT_EQ(r.threads, 4);
  EXPECT_EQ(r.labels, "set.json");
  EXPECT_EQ(r.bodies, "b.json");
  EXPECT_EQ(r.bodies_window, 3);
  EXPECT_EQ(r.bodies_degree, 1);
  EXPECT_EQ(r.outputs, (std::vector<std::string>{"c3d", "trc"}));
  EXPECT_EQ(RecipeToJson(r), doc);
}

TEST(ProcessingRecipe, AMinimalRecipeTakesTheDefaults) {
  const ProcessingRecipe r = RecipeFromJson(Minimal(), "r.json");
  const ProcessingRecipe defaults;
  EXPECT_EQ(RecipeToJson(r), RecipeToJson(defaults));
  EXPECT_EQ(r.outputs, (std::vector<std::string>{"trc"}));
  EXPECT_TRUE(r.calibration.empty());
  EXPECT_FALSE(r.force_calibration);
}

TEST(ProcessingRecipe, RefusesWithTheFieldAndTheRule) {
  EXPECT_NE(Refusal(nlohmann::json::array()).find("r.json: a recipe is a JSON object"), std::string::npos);
  EXPECT_NE(Refusal({{"version", 1}}).find("'format' must be \"mocap-recipe\""), std::string::npos);
  EXPECT_NE(Refusal({{"format", "mocap-recipe"}, {"version", 2}}).find("'version' must be 1"), std::string::npos);
  auto with = [](const char* key, nlohmann::json value) {
    nlohmann::json doc = Minimal();
    doc[key] = std::move(value);
    return Refusal(doc);
  };
  EXPECT_NE(with("matchr", "greedy").find("'matchr' is not a recipe field"), std::string::npos);
  EXPECT_NE(with("name", "../up").find("'name' must be letters"), std::string::npos);
  EXPECT_NE(with("name", ".hidden").find("'name'"), std::string::npos);
  EXPECT_NE(with("name", 7).find("'name' must be a string"), std::string::npos);
  EXPECT_NE(with("matcher", "magic").find("'matcher' is 'magic'; it must be one of clustering, greedy, relaxation"),
            std::string::npos);
  EXPECT_NE(with("predictions", "yes").find("'predictions' must be true or false"), std::string::npos);
  EXPECT_NE(with("threads", 0).find("'threads' must be a whole number 1-256"), std::string::npos);
  EXPECT_NE(with("threads", 2.5).find("'threads'"), std::string::npos);
  EXPECT_NE(with("max_spline_gap_s", -1).find("'max_spline_gap_s' must be a number 0-10"), std::string::npos);
  EXPECT_NE(with("outputs", nlohmann::json::array()).find("'outputs' must list"), std::string::npos);
  EXPECT_NE(with("outputs", {"trc", "bvh"}).find("'outputs' must list"), std::string::npos);
  EXPECT_NE(with("outputs", {"trc", "trc"}).find("'outputs' names trc twice"), std::string::npos);
  EXPECT_NE(with("labels", std::string(5000, 'a')).find("'labels' is longer than 4096"), std::string::npos);
}

}  // namespace
}  // namespace mocap::pipeline
