// Rigid bodies as the installation defines them: a name, its markers in the body's own frame
// (origin at the markers' centroid, axes those of the world when it was defined) and a pivot (the
// point whose position is reported, editable). Kept in a bodies file (JSON, editable by hand):
//   {"version": 1, "bodies": [{"name": "wand", "markers": [[x, y, z], ...], "pivot": [x, y, z]}]}
// Identity comes from inter-marker distances, so two bodies that share a congruent set of
// `start_markers` markers (the fewest the tracker starts from) cannot be told apart: such a
// definition is refused, naming the distances that collide.
// Errors: std::invalid_argument for definitions that cannot work, std::runtime_error "<file>:
// <reason>" for bodies files (the io layer's rule).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json_fwd.hpp>

namespace mocap {

struct RigidBodyDefinition {
  std::string name;
  std::vector<Eigen::Vector3d> markers;  // body frame, mm
  Eigen::Vector3d pivot = Eigen::Vector3d::Zero();
};

struct BodyDefinitionOptions {
  double min_marker_distance_mm = 10.0;  // closer markers merge in the cameras
  double distance_tolerance_mm = 3.0;    // as the tracker's: distances this close are equal
  size_t start_markers = 4;              // the fewest markers identity is decided from (the tracker's)
  // Markers defined together keep every distance between them within this (5th to 95th percentile
  // over the frames they are defined from): skin moves more, a rigid body within the noise.
  double rigidity_tolerance_mm = 6.0;
  void Check() const;                    // throws std::invalid_argument
};

// A body from its markers' world positions (at least 3, not collinear, none closer than
// min_marker_distance_mm). Throws std::invalid_argument naming the problem.
RigidBodyDefinition DefineBody(const std::string& name, const std::vector<Eigen::Vector3d>& world_markers,
                               const BodyDefinitionOptions& options = {});

// Why markers seen over several frames are not one rigid body, or empty when they are: the pair
// whose distance varies most, when its spread (5th to 95th percentile over the frames that see both)
// exceeds options.rigidity_tolerance_mm. frames[f][m]: marker m in frame f, NaN when not seen.
std::string RigidityProblem(const std::vector<std::vector<Eigen::Vector3d>>& frames,
                            const std::vector<std::string>& names, const BodyDefinitionOptions& options = {});

// Empty when `a` and `b` can be told apart; else which of their distances (mm) coincide.
std::string Ambiguity(const RigidBodyDefinition& a, const RigidBodyDefinition& b,
                      const BodyDefinitionOptions& options = {});

// Adds `body` to `bodies` (replacing one of the same name); throws std::invalid_argument when it
// is ambiguous with another body, with the reason.
void AddBody(std::vector<RigidBodyDefinition>& bodies, RigidBodyDefinition body,
             const BodyDefinitionOptions& options = {});

// The bodies file as JSON; `source` names it in errors ("<source>: <reason>", std::runtime_error).
std::vector<RigidBodyDefinition> BodiesFromJson(const nlohmann::json& doc, const std::string& source);
nlohmann::json BodiesToJson(const std::vector<RigidBodyDefinition>& bodies);

std::vector<RigidBodyDefinition> ReadBodiesFile(const std::string& path);
void WriteBodiesFile(const std::vector<RigidBodyDefinition>& bodies, const std::string& path);

}  // namespace mocap
