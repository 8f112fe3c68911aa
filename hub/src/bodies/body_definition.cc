// Rigid-body definitions, their ambiguity check and the bodies file (see body_definition.h).
#include "bodies/body_definition.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <utility>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "util/json_file.h"

namespace mocap {
namespace {

std::string Mm(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", v);
  return buf;
}

// A search for k markers of `a` congruent to k markers of `b`: a's subsets in lexicographic
// order, depth first, each prefix carrying every injective map of it into b that keeps all its
// pairwise distances within tolerance. A prefix no map fits is not extended, and a map's next
// marker is looked up among b's markers at the right distance from its first (b's distances
// sorted per marker), so the work follows the maps that survive (few for markers spread as
// bodies need), not C(n, k)^2 k! (two 64-marker bodies: 10^13 comparisons, a bodies file that
// never loaded). The first subset found is the lexicographically first one with a congruent
// partner, as an exhaustive search over the subsets finds.
class CongruenceSearch {
 public:
  CongruenceSearch(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b, size_t k,
                   double tolerance)
      : a_(a), b_(b), k_(k), tolerance_(tolerance), by_distance_(b.size()) {
    for (size_t j = 0; j < b.size(); ++j) {
      for (size_t other = 0; other < b.size(); ++other)
        if (other != j) by_distance_[j].push_back({(b[j] - b[other]).norm(), other});
      std::sort(by_distance_[j].begin(), by_distance_[j].end());
    }
  }

  // Whether there is such a subset; it is then subset().
  bool Find() {
    subset_.clear();
    return Extend({{}});
  }
  const std::vector<size_t>& subset() const { return subset_; }

 private:
  bool Extend(const std::vector<std::vector<size_t>>& maps) {
    if (subset_.size() == k_) return true;
    const size_t first = subset_.empty() ? 0 : subset_.back() + 1;
    for (size_t i = first; i + (k_ - subset_.size()) <= a_.size(); ++i) {
      std::vector<std::vector<size_t>> longer;
      for (const std::vector<size_t>& map : maps) {
        if (map.empty()) {
          for (size_t j = 0; j < b_.size(); ++j) longer.push_back({j});
          continue;
        }
        const double wanted = (a_[subset_[0]] - a_[i]).norm();
        const auto& near = by_distance_[map[0]];
        // The range a hair wider than the tolerance, the test itself exact.
        const double margin = tolerance_ + 1e-9 * (1.0 + wanted);
        auto it = std::lower_bound(near.begin(), near.end(), std::make_pair(wanted - margin, size_t{0}));
        for (; it != near.end() && it->first <= wanted + margin; ++it) {
          const size_t j = it->second;
          if (!(std::abs(wanted - it->first) <= tolerance_)) continue;
          if (std::find(map.begin(), map.end(), j) != map.end()) continue;
          bool fits = true;
          for (size_t t = 1; t < subset_.size() && fits; ++t)
            fits = std::abs((a_[subset_[t]] - a_[i]).norm() - (b_[map[t]] - b_[j]).norm()) <= tolerance_;
          if (!fits) continue;
          longer.push_back(map);
          longer.back().push_back(j);
        }
      }
      if (longer.empty()) continue;
      subset_.push_back(i);
      if (Extend(longer)) return true;
      subset_.pop_back();
    }
    return false;
  }

  const std::vector<Eigen::Vector3d>& a_;
  const std::vector<Eigen::Vector3d>& b_;
  size_t k_;
  double tolerance_;
  std::vector<std::vector<std::pair<double, size_t>>> by_distance_;  // per marker of b: (distance, other)
  std::vector<size_t> subset_;
};

Eigen::Vector3d Vec(const nlohmann::json& j, const std::string& where) {
  if (!j.is_array() || j.size() != 3) throw std::invalid_argument(where + " is not [x, y, z]");
  Eigen::Vector3d v;
  for (int k = 0; k < 3; ++k) {
    if (!j[static_cast<size_t>(k)].is_number()) throw std::invalid_argument(where + " is not [x, y, z]");
    v[k] = j[static_cast<size_t>(k)].get<double>();
  }
  if (!v.allFinite()) throw std::invalid_argument(where + " is not finite");
  return v;
}

}  // namespace

void BodyDefinitionOptions::Check() const {
  if (!(min_marker_distance_mm >= 0.0)) throw std::invalid_argument("min marker distance must be >= 0");
  if (!(distance_tolerance_mm > 0.0)) throw std::invalid_argument("distance tolerance must be > 0");
  if (start_markers < 3) throw std::invalid_argument("identity needs at least 3 markers");
  if (!(rigidity_tolerance_mm > 0.0)) throw std::invalid_argument("rigidity tolerance must be > 0");
}

std::string RigidityProblem(const std::vector<std::vector<Eigen::Vector3d>>& frames,
                            const std::vector<std::string>& names, const BodyDefinitionOptions& options) {
  options.Check();
  const size_t n = names.size();
  double worst = 0.0;
  size_t worst_a = 0, worst_b = 0;
  std::vector<double> distances;
  for (size_t a = 0; a < n; ++a)
    for (size_t b = a + 1; b < n; ++b) {
      distances.clear();
      for (const std::vector<Eigen::Vector3d>& frame : frames)
        if (frame.size() == n && frame[a].allFinite() && frame[b].allFinite())
          distances.push_back((frame[a] - frame[b]).norm());
      if (distances.size() < 2) continue;
      std::sort(distances.begin(), distances.end());
      const auto at = [&](double q) { return distances[static_cast<size_t>(q * static_cast<double>(distances.size() - 1))]; };
      const double spread = at(0.95) - at(0.05);
      if (spread > worst) worst = spread, worst_a = a, worst_b = b;
    }
  if (worst <= options.rigidity_tolerance_mm) return "";
  char text[64];
  std::snprintf(text, sizeof text, "%.1f mm", worst);
  return "not rigid: the distance between " + names[worst_a] + " and " + names[worst_b] + " varies by " + text +
         " over the frames (5th to 95th percentile; a rigid body's within " +
         std::to_string(static_cast<int>(options.rigidity_tolerance_mm)) +
         " mm): define it from its own markers (--markers) in frames where it moves as one piece";
}

RigidBodyDefinition DefineBody(const std::string& name, const std::vector<Eigen::Vector3d>& world_markers,
                               const BodyDefinitionOptions& options) {
  options.Check();
  if (name.empty() || name.size() > 63) throw std::invalid_argument("a body's name has 1 to 63 characters");
  if (world_markers.size() < 3)
    throw std::invalid_argument("body '" + name + "' has " + std::to_string(world_markers.size()) +
                                " markers; at least 3 are needed for a pose");
  for (size_t i = 0; i < world_markers.size(); ++i) {
    if (!world_markers[i].allFinite()) throw std::invalid_argument("body '" + name + "': a marker has no position");
    for (size_t j = i + 1; j < world_markers.size(); ++j)
      if ((world_markers[i] - world_markers[j]).norm() < options.min_marker_distance_mm)
        throw std::invalid_argument("body '" + name + "': markers " + std::to_string(i + 1) + " and " +
                                    std::to_string(j + 1) + " are " + Mm((world_markers[i] - world_markers[j]).norm()) +
                                    " mm apart (at least " + Mm(options.min_marker_distance_mm) + ")");
  }
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& m : world_markers) centroid += m;
  centroid /= static_cast<double>(world_markers.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& m : world_markers) scatter += (m - centroid) * (m - centroid).transpose();
  const Eigen::Vector3d spread = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter).eigenvalues();
  if (!(spread(1) > 1.0))  // mm^2: markers on (nearly) one line leave the rotation about it free
    throw std::invalid_argument("body '" + name + "': markers are (nearly) collinear; a pose needs them spread out");
  RigidBodyDefinition body;
  body.name = name;
  for (const Eigen::Vector3d& m : world_markers) body.markers.push_back(m - centroid);
  return body;
}

std::string Ambiguity(const RigidBodyDefinition& a, const RigidBodyDefinition& b, const BodyDefinitionOptions& options) {
  const size_t k = std::min({options.start_markers, a.markers.size(), b.markers.size()});
  CongruenceSearch search(a.markers, b.markers, k, 2.0 * options.distance_tolerance_mm);
  if (!search.Find()) return {};
  const std::vector<size_t>& sa = search.subset();
  std::string text = "'" + a.name + "' and '" + b.name + "' share " + std::to_string(k) +
                     " markers with the same distances (";
  for (size_t i = 0; i < sa.size(); ++i)
    for (size_t j = i + 1; j < sa.size(); ++j)
      text += (i == 0 && j == 1 ? "" : ", ") + Mm((a.markers[sa[i]] - a.markers[sa[j]]).norm());
  return text + " mm, within " + Mm(2.0 * options.distance_tolerance_mm) + " mm): move a marker";
}

void AddBody(std::vector<RigidBodyDefinition>& bodies, RigidBodyDefinition body, const BodyDefinitionOptions& options) {
  for (const RigidBodyDefinition& other : bodies) {
    if (other.name == body.name) continue;
    const std::string problem = Ambiguity(body, other, options);
    if (!problem.empty()) throw std::invalid_argument("ambiguous rigid body: " + problem);
  }
  auto same = std::find_if(bodies.begin(), bodies.end(), [&](const RigidBodyDefinition& b) { return b.name == body.name; });
  if (same != bodies.end())
    *same = std::move(body);
  else
    bodies.push_back(std::move(body));
}

std::vector<RigidBodyDefinition> BodiesFromJson(const nlohmann::json& doc, const std::string& source) {
  auto fail = [&](const std::string& why) { throw std::runtime_error(source + ": " + why); };
  if (!doc.is_object() || !doc.contains("version") || doc["version"] != 1 || !doc.contains("bodies") ||
      !doc["bodies"].is_array())
    fail("not a bodies file (expected {\"version\": 1, \"bodies\": [...]})");
  std::vector<RigidBodyDefinition> bodies;
  for (size_t i = 0; i < doc["bodies"].size(); ++i) {
    const nlohmann::json& j = doc["bodies"][i];
    const std::string where = "body " + std::to_string(i + 1);
    if (!j.is_object() || !j.contains("name") || !j["name"].is_string() || !j.contains("markers") ||
        !j["markers"].is_array())
      fail(where + " needs \"name\" and \"markers\"");
    try {
      std::vector<Eigen::Vector3d> markers;
      for (size_t m = 0; m < j["markers"].size() && m < 64; ++m)
        markers.push_back(Vec(j["markers"][m], where + " marker " + std::to_string(m + 1)));
      if (j["markers"].size() > 64) fail(where + " has more than 64 markers");
      // Re-defined from its own markers: the same checks as a new body, and a centred frame.
      RigidBodyDefinition body;
      body.name = j["name"].get<std::string>();
      body.markers = markers;
      DefineBody(body.name, markers);
      if (j.contains("pivot")) body.pivot = Vec(j["pivot"], where + " pivot");
      // AddBody replaces a body of the same name (a body defined again live); in a file two of
      // one name is a mistake that would keep the second unseen.
      for (size_t k = 0; k < bodies.size(); ++k) {
        if (bodies[k].name == body.name) fail(where + ": the name '" + body.name + "' is body " + std::to_string(k + 1) + "'s already");
      }
      AddBody(bodies, body);
    } catch (const std::invalid_argument& e) {
      fail(e.what());
    }
  }
  return bodies;
}

std::vector<RigidBodyDefinition> ReadBodiesFile(const std::string& path) {
  return BodiesFromJson(ReadJsonFile(path), path);
}

nlohmann::json BodiesToJson(const std::vector<RigidBodyDefinition>& bodies) {
  nlohmann::json list = nlohmann::json::array();
  for (const RigidBodyDefinition& b : bodies) {
    nlohmann::json markers = nlohmann::json::array();
    for (const Eigen::Vector3d& m : b.markers) markers.push_back({m.x(), m.y(), m.z()});
    list.push_back({{"name", b.name}, {"markers", markers}, {"pivot", {b.pivot.x(), b.pivot.y(), b.pivot.z()}}});
  }
  return {{"version", 1}, {"bodies", list}};
}

void WriteBodiesFile(const std::vector<RigidBodyDefinition>& bodies, const std::string& path) {
  WriteJsonFile(BodiesToJson(bodies), path);
}

}  // namespace mocap
