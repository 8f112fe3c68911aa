// libFuzzer entry for the bodies file reader: any JSON must load or throw runtime_error; bodies
// that load must be written and read back unchanged, and a tracker made of them must follow a
// frame of their own markers (apart from each other) with finite, unit poses.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include <nlohmann/json.hpp>

#include "bodies/body_definition.h"
#include "bodies/body_tracker.h"

namespace {

bool Same(const mocap::RigidBodyDefinition& a, const mocap::RigidBodyDefinition& b) {
  if (a.name != b.name || a.markers.size() != b.markers.size() || a.pivot != b.pivot) return false;
  for (size_t i = 0; i < a.markers.size(); ++i)
    if (a.markers[i] != b.markers[i]) return false;
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const nlohmann::json document = nlohmann::json::parse(data, data + size, nullptr, /*allow_exceptions=*/false);
  if (document.is_discarded()) return 0;
  std::vector<mocap::RigidBodyDefinition> bodies;
  try {
    bodies = mocap::BodiesFromJson(document, "fuzz");
  } catch (const std::runtime_error&) {
    return 0;
  }
  const std::vector<mocap::RigidBodyDefinition> again = mocap::BodiesFromJson(mocap::BodiesToJson(bodies), "again");
  if (again.size() != bodies.size()) __builtin_trap();
  for (size_t i = 0; i < bodies.size(); ++i)
    if (!Same(bodies[i], again[i])) __builtin_trap();
  if (bodies.empty()) return 0;
  // Each body's markers, bodies 10 m apart.
  std::vector<Eigen::Vector3d> points;
  for (size_t b = 0; b < bodies.size(); ++b)
    for (const Eigen::Vector3d& m : bodies[b].markers) points.push_back(m + Eigen::Vector3d(1e4 * b, 0.0, 0.0));
  mocap::BodyTracker tracker(bodies);
  for (int frame = 0; frame < 2; ++frame) {
    for (const mocap::BodyPose& pose : tracker.Update(points)) {
      if (!pose.tracked && !pose.predicted) continue;
      if (!(std::abs(pose.orientation.norm() - 1.0) < 1e-6) || !pose.position.allFinite() || !pose.pivot.allFinite())
        __builtin_trap();
    }
  }
  return 0;
}
