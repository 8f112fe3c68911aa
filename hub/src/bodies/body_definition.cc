// Rigid-body definitions, their ambiguity check and the bodies file (see body_definition.h).
#include "bodies/body_definition.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <stdexcept>

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

// Every `k`-subset of {0..n-1}, in lexicographic order.
std::vector<std::vector<size_t>> Subsets(size_t n, size_t k) {
  std::vector<std::vector<size_t>> out;
  if (k > n) return out;
  std::vector<size_t> idx(k);
  std::iota(idx.begin(), idx.end(), 0);
  while (true) {
    out.push_back(idx);
    size_t i = k;
    while (i > 0 && idx[i - 1] == n - k + i - 1) --i;
    if (i == 0) return out;
    ++idx[i - 1];
    for (size_t j = i; j < k; ++j) idx[j] = idx[j - 1] + 1;
  }
}

// Whether some bijection maps subset `sa` of `a` onto subset `sb` of `b` with all pairwise
// distances within tolerance; the matched distances go to `collide`.
bool Congruent(const std::vector<Eigen::Vector3d>& a, const std::vector<size_t>& sa,
               const std::vector<Eigen::Vector3d>& b, std::vector<size_t> sb, double tolerance,
               std::vector<double>* collide) {
  std::sort(sb.begin(), sb.end());
  do {
    bool all = true;
    for (size_t i = 0; i < sa.size() && all; ++i)
      for (size_t j = i + 1; j < sa.size() && all; ++j)
        all = std::abs((a[sa[i]] - a[sa[j]]).norm() - (b[sb[i]] - b[sb[j]]).norm()) <= tolerance;
    if (all) {
      collide->clear();
      for (size_t i = 0; i < sa.size(); ++i)
        for (size_t j = i + 1; j < sa.size(); ++j) collide->push_back((a[sa[i]] - a[sa[j]]).norm());
      return true;
    }
  } while (std::next_permutation(sb.begin(), sb.end()));
  return false;
}

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
  std::vector<double> collide;
  for (const auto& sa : Subsets(a.markers.size(), k))
    for (const auto& sb : Subsets(b.markers.size(), k))
      if (Congruent(a.markers, sa, b.markers, sb, 2.0 * options.distance_tolerance_mm, &collide)) {
        std::string text = "'" + a.name + "' and '" + b.name + "' share " + std::to_string(k) +
                           " markers with the same distances (";
        for (size_t i = 0; i < collide.size(); ++i) text += (i ? ", " : "") + Mm(collide[i]);
        return text + " mm, within " + Mm(2.0 * options.distance_tolerance_mm) + " mm): move a marker";
      }
  return {};
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

std::vector<RigidBodyDefinition> ReadBodiesFile(const std::string& path) {
  const nlohmann::json doc = ReadJsonFile(path);
  auto fail = [&](const std::string& why) { throw std::runtime_error(path + ": " + why); };
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
      AddBody(bodies, body);
    } catch (const std::invalid_argument& e) {
      fail(e.what());
    }
  }
  return bodies;
}

void WriteBodiesFile(const std::vector<RigidBodyDefinition>& bodies, const std::string& path) {
  nlohmann::json list = nlohmann::json::array();
  for (const RigidBodyDefinition& b : bodies) {
    nlohmann::json markers = nlohmann::json::array();
    for (const Eigen::Vector3d& m : b.markers) markers.push_back({m.x(), m.y(), m.z()});
    list.push_back({{"name", b.name}, {"markers", markers}, {"pivot", {b.pivot.x(), b.pivot.y(), b.pivot.z()}}});
  }
  WriteJsonFile({{"version", 1}, {"bodies", list}}, path);
}

}  // namespace mocap
