// A processing recipe: how recorded sessions become results, written once as a JSON file and
// applied to any number of sessions (`mocap-hub process RECIPE SESSIONS...`, one session per task
// on a cluster): the reconstruction's choices, the whole-take steps (names, rigid bodies) and the
// files to write. Each session's results go to SESSION/processed/NAME/, beside the raw log and
// never over it.
//
//   {"format": "mocap-recipe", "version": 1,
//    "name": "gait",                        plain name (letters, digits, . - _), 1-64 characters
//    "calibration": "rig.json",             optional: else each session's own calibration
//    "force_calibration": false,            true: reconstruct with a calibration that does not fit
//                                           the session (calib/calibration_fit.h), with a warning
//    "matcher": "relaxation",               relaxation | clustering | greedy
//    "assignment": "optimal",               optimal | greedy
//    "predictions": true, "hindsight_swaps": true,
//    "max_spline_gap_s": 0.05,              longest gap filled by a spline, 0-10 s
//    "threads": 1,                          inside a frame, 1-256 (results identical for any count)
//    "labels": "set.json",                  optional marker set (labels learn)
//    "bodies": "bodies.json",               optional rigid bodies
//    "bodies_window": 6, "bodies_degree": 2,
//    "outputs": ["trc", "c3d"]}             one or both
//
// Relative paths are the recipe file's own (the caller resolves them). Every field but format and
// version is optional; unknown fields are refused (a misspelt option must not pass unnoticed).
// Errors: std::invalid_argument naming the source, the field and the rule.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace mocap::pipeline {

struct ProcessingRecipe {
  std::string name = "default";
  std::string calibration;
  bool force_calibration = false;
  std::string matcher = "relaxation";
  std::string assignment = "optimal";
  bool predictions = true;
  bool hindsight_swaps = true;
  double max_spline_gap_s = 0.05;
  int threads = 1;
  std::string labels;
  std::string bodies;
  int bodies_window = 6;
  int bodies_degree = 2;
  std::vector<std::string> outputs = {"trc"};
};

ProcessingRecipe RecipeFromJson(const nlohmann::json& doc, const std::string& source);
nlohmann::json RecipeToJson(const ProcessingRecipe& recipe);

}  // namespace mocap::pipeline
