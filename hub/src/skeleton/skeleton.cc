// The skeleton model, its checks and its JSON file.
#include "skeleton/skeleton.h"

#include <cmath>
#include <set>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "util/json_file.h"

namespace mocap {
namespace {

using nlohmann::json;

bool Finite(const Eigen::Vector3d& v) { return v.allFinite() && v.cwiseAbs().maxCoeff() < 1e7; }

json VectorJson(const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); }

Eigen::Vector3d VectorFrom(const json& value, const std::string& what) {
  if (!value.is_array() || value.size() != 3) throw std::invalid_argument(what + ": not an array of 3 numbers");
  Eigen::Vector3d v;
  for (int i = 0; i < 3; ++i) {
    if (!value[i].is_number()) throw std::invalid_argument(what + ": not an array of 3 numbers");
    v[i] = value[i].get<double>();
  }
  if (!Finite(v)) throw std::invalid_argument(what + ": not finite or beyond 1e7 mm");
  return v;
}

double NumberFrom(const json& object, const char* key, double fallback, const std::string& what) {
  if (!object.contains(key)) return fallback;
  if (!object[key].is_number()) throw std::invalid_argument(what + "." + key + ": not a number");
  return object[key].get<double>();
}

bool BoolFrom(const json& object, const char* key, const std::string& what) {
  if (!object.contains(key)) return false;
  if (!object[key].is_boolean()) throw std::invalid_argument(what + "." + key + ": not true or false");
  return object[key].get<bool>();
}

std::string StringFrom(const json& object, const char* key, const std::string& what) {
  if (!object.contains(key) || !object[key].is_string())
    throw std::invalid_argument(what + "." + key + ": missing or not a string");
  return object[key].get<std::string>();
}

int AxisFrom(const std::string& name, const std::string& what) {
  if (name == "x") return 0;
  if (name == "y") return 1;
  if (name == "z") return 2;
  throw std::invalid_argument(what + ".axis: \"" + name + "\" is not x, y or z");
}

}  // namespace

char AxisName(int axis) { return static_cast<char>('x' + axis); }

size_t Skeleton::NumPoseParameters() const {
  size_t n = 3;
  for (const auto& s : segments) n += s.dofs.size();
  return n;
}

size_t Skeleton::FirstDof(size_t s) const {
  size_t n = 3;
  for (size_t i = 0; i < s; ++i) n += segments[i].dofs.size();
  return n;
}

int Skeleton::FindSegment(const std::string& name) const {
  for (size_t i = 0; i < segments.size(); ++i)
    if (segments[i].name == name) return static_cast<int>(i);
  return -1;
}

int Skeleton::FindMarker(const std::string& name) const {
  for (size_t i = 0; i < markers.size(); ++i)
    if (markers[i].name == name) return static_cast<int>(i);
  return -1;
}

std::vector<std::vector<int>> Skeleton::Children() const {
  std::vector<std::vector<int>> children(segments.size());
  for (size_t i = 1; i < segments.size(); ++i) children[segments[i].parent].push_back(static_cast<int>(i));
  return children;
}

void Skeleton::Check() const {
  if (segments.empty()) throw std::invalid_argument("segments: none (a skeleton needs a root)");
  if (segments.size() > kMaxSkeletonSegments)
    throw std::invalid_argument("segments: " + std::to_string(segments.size()) + " is more than " +
                                std::to_string(kMaxSkeletonSegments));
  if (markers.size() > kMaxSkeletonMarkers)
    throw std::invalid_argument("markers: " + std::to_string(markers.size()) + " is more than " +
                                std::to_string(kMaxSkeletonMarkers));
  std::set<std::string> names;
  for (size_t i = 0; i < segments.size(); ++i) {
    const SkeletonSegment& s = segments[i];
    const std::string what = "segment \"" + s.name + "\"";
    if (s.name.empty() || s.name.find_first_of(" \t\r\n{}") != std::string::npos)
      throw std::invalid_argument(what + ": a name must be non-empty without spaces or braces");
    if (!names.insert(s.name).second) throw std::invalid_argument(what + ": name used twice");
    if (i == 0 && s.parent != -1) throw std::invalid_argument(what + ": the first segment is the root (no parent)");
    if (i > 0 && (s.parent < 0 || s.parent >= static_cast<int>(i)))
      throw std::invalid_argument(what + ": parent must be an earlier segment");
    if (i == 0 && s.dofs.size() != 3) throw std::invalid_argument(what + ": the root has exactly 3 rotations");
    if (i > 0 && (s.dofs.empty() || s.dofs.size() > 3))
      throw std::invalid_argument(what + ": " + std::to_string(s.dofs.size()) + " dofs, must be 1 to 3");
    for (size_t k = 0; k < s.dofs.size(); ++k) {
      const JointDof& d = s.dofs[k];
      if (d.axis < 0 || d.axis > 2) throw std::invalid_argument(what + ": dof axis out of range");
      if (k > 0 && d.axis == s.dofs[k - 1].axis)
        throw std::invalid_argument(what + ": two successive rotations about " + AxisName(d.axis));
      if (!(d.min_deg >= -180.0 && d.min_deg <= d.max_deg && d.max_deg <= 180.0))
        throw std::invalid_argument(what + ": dof " + AxisName(d.axis) + " limits [" + std::to_string(d.min_deg) +
                                    ", " + std::to_string(d.max_deg) + "] not within -180 <= min <= max <= 180");
    }
    if (!Finite(s.offset) || !Finite(s.end)) throw std::invalid_argument(what + ": offset or end not finite");
    if (s.bone && s.offset.norm() < 1e-6) throw std::invalid_argument(what + ": a bone needs a non-zero offset");
  }
  std::set<std::string> marker_names;
  for (const SkeletonMarker& m : markers) {
    const std::string what = "marker \"" + m.name + "\"";
    if (m.name.empty()) throw std::invalid_argument("markers: an empty name");
    if (!marker_names.insert(m.name).second) throw std::invalid_argument(what + ": name used twice");
    if (m.segment < 0 || m.segment >= static_cast<int>(segments.size()))
      throw std::invalid_argument(what + ": segment out of range");
    if (!Finite(m.offset)) throw std::invalid_argument(what + ": offset not finite");
    if (!(m.weight > 0.0 && m.weight <= 100.0))
      throw std::invalid_argument(what + ": weight " + std::to_string(m.weight) + " not in (0, 100]");
  }
}

nlohmann::json SkeletonToJson(const Skeleton& skeleton) {
  json segments = json::array();
  for (const SkeletonSegment& s : skeleton.segments) {
    json dofs = json::array();
    for (const JointDof& d : s.dofs)
      dofs.push_back({{"axis", std::string(1, AxisName(d.axis))}, {"min", d.min_deg}, {"max", d.max_deg}});
    json segment = {{"name", s.name},
                    {"parent", s.parent < 0 ? json(nullptr) : json(skeleton.segments[s.parent].name)},
                    {"offset", VectorJson(s.offset)},
                    {"dofs", dofs},
                    {"end", VectorJson(s.end)}};
    if (s.bone) segment["bone"] = true;
    if (s.reference_zero) segment["reference_zero"] = true;
    segments.push_back(segment);
  }
  json markers = json::array();
  for (const SkeletonMarker& m : skeleton.markers)
    markers.push_back({{"name", m.name},
                       {"segment", skeleton.segments[m.segment].name},
                       {"offset", VectorJson(m.offset)},
                       {"weight", m.weight}});
  return {{"version", 1}, {"type", "skeleton"}, {"calibrated", skeleton.calibrated},
          {"segments", segments}, {"markers", markers}};
}

Skeleton SkeletonFromJson(const nlohmann::json& document, const std::string& source) {
  try {
    if (!document.is_object()) throw std::invalid_argument("not a JSON object");
    if (StringFrom(document, "type", "document") != "skeleton")
      throw std::invalid_argument("type: not \"skeleton\"");
    if (!document.contains("version") || !document["version"].is_number_integer() || document["version"] != 1)
      throw std::invalid_argument("version: only 1 is known");
    Skeleton skeleton;
    skeleton.calibrated = BoolFrom(document, "calibrated", "document");
    if (!document.contains("segments") || !document["segments"].is_array())
      throw std::invalid_argument("segments: missing or not an array");
    if (!document.contains("markers") || !document["markers"].is_array())
      throw std::invalid_argument("markers: missing or not an array");
    const json& segments = document["segments"];
    if (segments.size() > kMaxSkeletonSegments)
      throw std::invalid_argument("segments: more than " + std::to_string(kMaxSkeletonSegments));
    if (document["markers"].size() > kMaxSkeletonMarkers)
      throw std::invalid_argument("markers: more than " + std::to_string(kMaxSkeletonMarkers));
    for (size_t i = 0; i < segments.size(); ++i) {
      const json& item = segments[i];
      const std::string what = "segments[" + std::to_string(i) + "]";
      if (!item.is_object()) throw std::invalid_argument(what + ": not an object");
      SkeletonSegment s;
      s.name = StringFrom(item, "name", what);
      if (!item.contains("parent")) throw std::invalid_argument(what + ".parent: missing (null for the root)");
      if (!item["parent"].is_null()) {
        if (!item["parent"].is_string()) throw std::invalid_argument(what + ".parent: not a name or null");
        s.parent = skeleton.FindSegment(item["parent"].get<std::string>());
        if (s.parent < 0)
          throw std::invalid_argument(what + ".parent: \"" + item["parent"].get<std::string>() +
                                      "\" is not an earlier segment");
      }
      s.offset = item.contains("offset") ? VectorFrom(item["offset"], what + ".offset") : Eigen::Vector3d::Zero();
      s.end = item.contains("end") ? VectorFrom(item["end"], what + ".end") : Eigen::Vector3d::Zero();
      s.bone = BoolFrom(item, "bone", what);
      s.reference_zero = BoolFrom(item, "reference_zero", what);
      if (!item.contains("dofs") || !item["dofs"].is_array() || item["dofs"].size() > 3)
        throw std::invalid_argument(what + ".dofs: missing or not an array of at most 3");
      for (const json& dof : item["dofs"]) {
        if (!dof.is_object()) throw std::invalid_argument(what + ".dofs: an entry is not an object");
        JointDof d;
        d.axis = AxisFrom(StringFrom(dof, "axis", what + ".dofs"), what + ".dofs");
        d.min_deg = NumberFrom(dof, "min", -180.0, what + ".dofs");
        d.max_deg = NumberFrom(dof, "max", 180.0, what + ".dofs");
        s.dofs.push_back(d);
      }
      skeleton.segments.push_back(s);
    }
    for (const json& item : document["markers"]) {
      if (!item.is_object()) throw std::invalid_argument("markers: an entry is not an object");
      SkeletonMarker m;
      m.name = StringFrom(item, "name", "markers");
      const std::string what = "marker \"" + m.name + "\"";
      const std::string segment = StringFrom(item, "segment", what);
      m.segment = skeleton.FindSegment(segment);
      if (m.segment < 0) throw std::invalid_argument(what + ".segment: \"" + segment + "\" is not a segment");
      m.offset = item.contains("offset") ? VectorFrom(item["offset"], what + ".offset") : Eigen::Vector3d::Zero();
      m.weight = NumberFrom(item, "weight", 1.0, what);
      skeleton.markers.push_back(m);
    }
    skeleton.Check();
    return skeleton;
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error(source + ": " + error.what());
  } catch (const nlohmann::json::exception& error) {
    throw std::runtime_error(source + ": " + error.what());
  }
}

Skeleton ReadSkeletonFile(const std::string& path) { return SkeletonFromJson(ReadJsonFile(path), path); }

void WriteSkeletonFile(const Skeleton& skeleton, const std::string& path) {
  WriteJsonFile(SkeletonToJson(skeleton), path);
}

}  // namespace mocap
