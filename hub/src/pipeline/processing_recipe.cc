// Processing recipes from and to JSON (see processing_recipe.h).
#include "pipeline/processing_recipe.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "util/plain_name.h"

namespace mocap::pipeline {
namespace {

constexpr size_t kMaxPathSize = 4096;

class RecipeReader {
 public:
  RecipeReader(const nlohmann::json& doc, const std::string& source) : doc_(doc), source_(source) {}

  [[noreturn]] void Refuse(const std::string& field, const std::string& rule) const {
    throw std::invalid_argument(source_ + ": recipe field '" + field + "' " + rule);
  }

  const nlohmann::json* Field(const char* name) const {
    const auto it = doc_.find(name);
    return it == doc_.end() ? nullptr : &*it;
  }

  void String(const char* name, std::string* value, size_t max_size) const {
    const nlohmann::json* j = Field(name);
    if (!j) return;
    if (!j->is_string()) Refuse(name, "must be a string");
    *value = j->get<std::string>();
    if (value->size() > max_size) Refuse(name, "is longer than " + std::to_string(max_size) + " characters");
  }

  void OneOf(const char* name, std::string* value, const std::set<std::string>& allowed) const {
    String(name, value, 64);
    if (!allowed.count(*value)) Refuse(name, "is '" + *value + "'; it must be one of " + Join(allowed));
  }

  void Bool(const char* name, bool* value) const {
    const nlohmann::json* j = Field(name);
    if (!j) return;
    if (!j->is_boolean()) Refuse(name, "must be true or false");
    *value = j->get<bool>();
  }

  void Int(const char* name, int* value, int low, int high) const {
    const nlohmann::json* j = Field(name);
    if (!j) return;
    if (!j->is_number_integer() || j->get<long long>() < low || j->get<long long>() > high)
      Refuse(name, "must be a whole number " + std::to_string(low) + "-" + std::to_string(high));
    *value = j->get<int>();
  }

  void Number(const char* name, double* value, double low, double high) const {
    const nlohmann::json* j = Field(name);
    if (!j) return;
    if (!j->is_number() || !std::isfinite(j->get<double>()) || j->get<double>() < low || j->get<double>() > high)
      Refuse(name, "must be a number " + Format(low) + "-" + Format(high));
    *value = j->get<double>();
  }

  static std::string Join(const std::set<std::string>& words) {
    std::string out;
    for (const std::string& w : words) out += (out.empty() ? "" : ", ") + w;
    return out;
  }
  static std::string Format(double v) {
    std::string s = std::to_string(v);
    s.erase(s.find_last_not_of('0') + 1);
    if (!s.empty() && s.back() == '.') s.pop_back();
    return s;
  }

 private:
  const nlohmann::json& doc_;
  const std::string& source_;
};

const std::set<std::string> kFields = {"format",      "version",         "name",    "calibration",      "force_calibration", "matcher",
                                       "assignment",  "predictions",     "hindsight_swaps", "max_spline_gap_s",
                                       "threads",     "labels",          "bodies",  "bodies_window",    "bodies_degree",
                                       "outputs"};

}  // namespace

ProcessingRecipe RecipeFromJson(const nlohmann::json& doc, const std::string& source) {
  if (!doc.is_object()) throw std::invalid_argument(source + ": a recipe is a JSON object");
  RecipeReader read(doc, source);
  if (doc.value("format", nlohmann::json()) != "mocap-recipe")
    read.Refuse("format", "must be \"mocap-recipe\"");
  if (doc.value("version", nlohmann::json()) != 1) read.Refuse("version", "must be 1 (the version this hub reads)");
  for (const auto& item : doc.items())
    if (!kFields.count(item.key())) read.Refuse(item.key(), "is not a recipe field (" + RecipeReader::Join(kFields) + ")");
  ProcessingRecipe r;
  read.String("name", &r.name, 64);
  if (!PlainName(r.name, 64)) read.Refuse("name", "must be letters, digits, '.', '-' or '_', not starting with '.'");
  read.String("calibration", &r.calibration, kMaxPathSize);
  read.Bool("force_calibration", &r.force_calibration);
  read.OneOf("matcher", &r.matcher, {"relaxation", "clustering", "greedy"});
  read.OneOf("assignment", &r.assignment, {"optimal", "greedy"});
  read.Bool("predictions", &r.predictions);
  read.Bool("hindsight_swaps", &r.hindsight_swaps);
  read.Number("max_spline_gap_s", &r.max_spline_gap_s, 0.0, 10.0);
  read.Int("threads", &r.threads, 1, 256);
  read.String("labels", &r.labels, kMaxPathSize);
  read.String("bodies", &r.bodies, kMaxPathSize);
  read.Int("bodies_window", &r.bodies_window, 0, 50);
  read.Int("bodies_degree", &r.bodies_degree, 1, 3);
  if (const nlohmann::json* outputs = read.Field("outputs")) {
    if (!outputs->is_array() || outputs->empty() || outputs->size() > 2) read.Refuse("outputs", "must list \"trc\", \"c3d\" or both");
    r.outputs.clear();
    for (const nlohmann::json& o : *outputs) {
      if (!o.is_string() || (o != "trc" && o != "c3d")) read.Refuse("outputs", "must list \"trc\", \"c3d\" or both");
      if (std::find(r.outputs.begin(), r.outputs.end(), o.get<std::string>()) != r.outputs.end())
        read.Refuse("outputs", "names " + o.get<std::string>() + " twice");
      r.outputs.push_back(o.get<std::string>());
    }
  }
  return r;
}

nlohmann::json RecipeToJson(const ProcessingRecipe& r) {
  nlohmann::json j = {{"format", "mocap-recipe"},
                      {"version", 1},
                      {"name", r.name},
                      {"force_calibration", r.force_calibration},
                      {"matcher", r.matcher},
                      {"assignment", r.assignment},
                      {"predictions", r.predictions},
                      {"hindsight_swaps", r.hindsight_swaps},
                      {"max_spline_gap_s", r.max_spline_gap_s},
                      {"threads", r.threads},
                      {"bodies_window", r.bodies_window},
                      {"bodies_degree", r.bodies_degree},
                      {"outputs", r.outputs}};
  if (!r.calibration.empty()) j["calibration"] = r.calibration;
  if (!r.labels.empty()) j["labels"] = r.labels;
  if (!r.bodies.empty()) j["bodies"] = r.bodies;
  return j;
}

}  // namespace mocap::pipeline
