// libFuzzer entry for the skeleton file: any bytes load or throw runtime_error; a skeleton that
// loads survives a write and read back, forward kinematics and a solve of its own rest markers.
#include <cstddef>
#include <cstdint>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "skeleton/kinematics.h"
#include "skeleton/skeleton.h"
#include "skeleton/skeleton_solver.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const nlohmann::json document = nlohmann::json::parse(data, data + size, nullptr, /*allow_exceptions=*/false);
  if (document.is_discarded()) return 0;
  try {
    const mocap::Skeleton skeleton = mocap::SkeletonFromJson(document, "fuzz");
    const mocap::Skeleton again = mocap::SkeletonFromJson(mocap::SkeletonToJson(skeleton), "fuzz-again");
    if (again.NumSegments() != skeleton.NumSegments() || again.markers.size() != skeleton.markers.size())
      __builtin_trap();
    std::vector<double> pose(skeleton.NumPoseParameters(), 0.1);
    mocap::SkeletonPoseState state;
    mocap::ForwardKinematics(skeleton, pose.data(), nullptr, &state);
    std::vector<Eigen::Vector3d> points;
    for (const auto& m : skeleton.markers) points.push_back(mocap::MarkerInSkeleton(state, m.segment, m.offset));
    mocap::SkeletonSolveOptions options;
    options.max_iterations = 5;
    options.warm_iterations = 5;
    mocap::SkeletonSolver solver(skeleton, options);
    solver.Solve(points);
  } catch (const std::runtime_error&) {
  }
  return 0;
}
