// Marker-set JSON (see marker_set.h).
#include "labels/marker_set.h"

#include <cmath>
#include <set>
#include <stdexcept>
#include <unordered_map>

#include <nlohmann/json.hpp>

#include "util/json_file.h"

namespace mocap {

int MarkerSet::Find(const std::string& name) const {
  for (size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return static_cast<int>(i);
  return -1;
}

int MarkerSet::SegmentOf(int marker) const {
  if (marker < 0 || static_cast<size_t>(marker) >= segment_of_.size()) return -1;
  return segment_of_[static_cast<size_t>(marker)];
}

const MarkerDistance* MarkerSet::Distance(int a, int b) const {
  const size_t n = names.size();
  if (a < 0 || b < 0 || static_cast<size_t>(a) >= n || static_cast<size_t>(b) >= n || a == b) return nullptr;
  if (a > b) std::swap(a, b);
  if (distance_index_.size() != n * n) return nullptr;
  const int i = distance_index_[static_cast<size_t>(a) * n + static_cast<size_t>(b)];
  return i < 0 ? nullptr : &distances[static_cast<size_t>(i)];
}

void MarkerSet::Index() {
  const size_t n = names.size();
  segment_of_.assign(n, -1);
  for (size_t s = 0; s < segments.size(); ++s)
    for (int m : segments[s]) segment_of_[static_cast<size_t>(m)] = static_cast<int>(s);
  distance_index_.assign(n * n, -1);
  for (size_t i = 0; i < distances.size(); ++i)
    distance_index_[static_cast<size_t>(distances[i].a) * n + static_cast<size_t>(distances[i].b)] = static_cast<int>(i);
}

nlohmann::json MarkerSetToJson(const MarkerSet& set) {
  nlohmann::json markers = nlohmann::json::array();
  for (size_t i = 0; i < set.names.size(); ++i) {
    const Eigen::Vector3d& m = set.mean_shape[i];
    nlohmann::json mean = m.allFinite() ? nlohmann::json::array({m.x(), m.y(), m.z()}) : nlohmann::json(nullptr);
    markers.push_back({{"name", set.names[i]}, {"mean", mean}});
  }
  nlohmann::json segments = nlohmann::json::array();
  for (const std::vector<int>& s : set.segments) {
    nlohmann::json names = nlohmann::json::array();
    for (int m : s) names.push_back(set.names[static_cast<size_t>(m)]);
    segments.push_back(names);
  }
  nlohmann::json distances = nlohmann::json::array();
  for (const MarkerDistance& d : set.distances)
    distances.push_back({{"a", set.names[static_cast<size_t>(d.a)]}, {"b", set.names[static_cast<size_t>(d.b)]},
                         {"mean", d.mean}, {"sd", d.sd}, {"min", d.min}, {"max", d.max}, {"frames", d.frames}});
  return {{"version", 1}, {"type", "marker-set"}, {"markers", markers}, {"segments", segments}, {"distances", distances}};
}

namespace {

double Number(const nlohmann::json& j, const char* key, const std::string& where) {
  if (!j.contains(key) || !j[key].is_number()) throw std::runtime_error(where + ": \"" + key + "\" must be a number");
  const double v = j[key].get<double>();
  if (!std::isfinite(v) || v < 0.0 || v > 1e6) throw std::runtime_error(where + ": \"" + key + "\" out of range");
  return v;
}

}  // namespace

MarkerSet MarkerSetFromJson(const nlohmann::json& doc, const std::string& source) {
  auto fail = [&](const std::string& why) { throw std::runtime_error(source + ": " + why); };
  if (!doc.is_object() || !doc.contains("version") || !doc["version"].is_number_integer() || doc["version"] != 1 ||
      !doc.contains("type") || doc["type"] != "marker-set")
    fail("not a marker set (expected {\"version\": 1, \"type\": \"marker-set\", ...})");
  if (!doc.contains("markers") || !doc["markers"].is_array() || doc["markers"].empty())
    fail("\"markers\" must be a non-empty list");
  if (doc["markers"].size() > kMaxMarkerSetMarkers)
    fail("more than " + std::to_string(kMaxMarkerSetMarkers) + " markers");
  MarkerSet set;
  std::unordered_map<std::string, int> index;
  for (size_t i = 0; i < doc["markers"].size(); ++i) {
    const nlohmann::json& m = doc["markers"][i];
    const std::string where = "marker " + std::to_string(i + 1);
    if (!m.is_object() || !m.contains("name") || !m["name"].is_string()) fail(where + " needs a \"name\"");
    const std::string name = m["name"].get<std::string>();
    if (name.empty() || name.size() > 255) fail(where + ": a name is 1-255 bytes");
    if (!index.emplace(name, static_cast<int>(i)).second) fail(where + ": name '" + name + "' given twice");
    Eigen::Vector3d mean = Eigen::Vector3d::Constant(std::nan(""));
    if (m.contains("mean") && !m["mean"].is_null()) {
      const nlohmann::json& v = m["mean"];
      if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
        fail(where + ": \"mean\" must be [x, y, z] or null");
      mean = Eigen::Vector3d(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
      if (!mean.allFinite() || mean.cwiseAbs().maxCoeff() > 1e6) fail(where + ": \"mean\" out of range");
    }
    set.names.push_back(name);
    set.mean_shape.push_back(mean);
  }
  auto marker_of = [&](const nlohmann::json& name, const std::string& where) {
    if (!name.is_string()) fail(where + ": a marker name must be a string");
    const auto it = index.find(name.get<std::string>());
    if (it == index.end()) fail(where + ": unknown marker '" + name.get<std::string>() + "'");
    return it->second;
  };
  if (doc.contains("segments")) {
    if (!doc["segments"].is_array()) fail("\"segments\" must be a list");
    std::set<int> used;
    for (size_t s = 0; s < doc["segments"].size(); ++s) {
      const nlohmann::json& seg = doc["segments"][s];
      const std::string where = "segment " + std::to_string(s + 1);
      if (!seg.is_array() || seg.size() < 2) fail(where + " must list at least 2 markers");
      std::vector<int> members;
      for (const nlohmann::json& name : seg) {
        const int m = marker_of(name, where);
        if (!used.insert(m).second) fail(where + ": marker '" + set.names[static_cast<size_t>(m)] + "' is in two segments");
        members.push_back(m);
      }
      set.segments.push_back(members);
    }
  }
  if (doc.contains("distances")) {
    if (!doc["distances"].is_array()) fail("\"distances\" must be a list");
    const size_t n = set.names.size();
    if (doc["distances"].size() > n * (n - 1) / 2) fail("more distances than pairs of markers");
    std::set<std::pair<int, int>> seen;
    for (size_t i = 0; i < doc["distances"].size(); ++i) {
      const nlohmann::json& d = doc["distances"][i];
      const std::string where = "distance " + std::to_string(i + 1);
      if (!d.is_object() || !d.contains("a") || !d.contains("b")) fail(where + " needs \"a\" and \"b\"");
      MarkerDistance out;
      out.a = marker_of(d["a"], where);
      out.b = marker_of(d["b"], where);
      if (out.a == out.b) fail(where + ": a marker's distance to itself");
      if (out.a > out.b) std::swap(out.a, out.b);
      if (!seen.insert({out.a, out.b}).second) fail(where + ": pair given twice");
      out.mean = Number(d, "mean", where);
      out.sd = Number(d, "sd", where);
      out.min = Number(d, "min", where);
      out.max = Number(d, "max", where);
      if (!(out.min <= out.mean && out.mean <= out.max)) fail(where + ": needs min <= mean <= max");
      out.frames = static_cast<size_t>(Number(d, "frames", where));
      set.distances.push_back(out);
    }
  }
  set.Index();
  return set;
}

MarkerSet ReadMarkerSetFile(const std::string& path) { return MarkerSetFromJson(ReadJsonFile(path), path); }

void WriteMarkerSetFile(const MarkerSet& set, const std::string& path) { WriteJsonFile(MarkerSetToJson(set), path); }

}  // namespace mocap
