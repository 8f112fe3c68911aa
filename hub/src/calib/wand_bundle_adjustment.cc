// Ceres problem for the wand bundle: poses and intrinsics as flat blocks (camera_blocks.h),
// wand axes on the unit sphere, Schur elimination of the many wand blocks.
#include "calib/wand_bundle_adjustment.h"

#include <array>
#include <memory>
#include <stdexcept>

#include <ceres/loss_function.h>
#include <ceres/manifold.h>
#include <ceres/problem.h>
#include <ceres/product_manifold.h>
#include <ceres/solver.h>
#include <ceres/sphere_manifold.h>

#include "calib/camera_blocks.h"
#include "calib/cost_functions.h"

namespace mocap {
namespace {

using WandPoseManifold = ceres::ProductManifold<ceres::EuclideanManifold<3>, ceres::SphereManifold<3>>;

}  // namespace

const char* IntrinsicsRefinementName(IntrinsicsRefinement refinement) {
  switch (refinement) {
    case IntrinsicsRefinement::kNone: return "none";
    case IntrinsicsRefinement::kFocalAndPrincipal: return "focal-principal";
    case IntrinsicsRefinement::kAll: return "all";
  }
  return "unknown";
}

IntrinsicsRefinement IntrinsicsRefinementFromName(const std::string& name) {
  for (IntrinsicsRefinement r : {IntrinsicsRefinement::kNone, IntrinsicsRefinement::kFocalAndPrincipal,
                                 IntrinsicsRefinement::kAll}) {
    if (name == IntrinsicsRefinementName(r)) return r;
  }
  throw std::invalid_argument("unknown intrinsics refinement '" + name + "' (none, focal-principal, all)");
}

void WandBundleOptions::Check() const {
  if (!(loss_scale_px > 0.0)) throw std::invalid_argument("loss_scale_px must be > 0");
  if (max_iterations < 1) throw std::invalid_argument("max_iterations must be >= 1");
  if (num_threads < 1) throw std::invalid_argument("num_threads must be >= 1");
}

WandBundleSummary AdjustWandBundle(const std::vector<WandFrame>& frames, const WandGeometry& wand,
                                   const WandBundleOptions& options, const std::vector<bool>& active,
                                   std::vector<Camera>* cameras, std::vector<WandPose>* wand_poses) {
  options.Check();
  const size_t n = cameras->size();
  if (active.size() != n || wand_poses->size() != frames.size()) {
    throw std::invalid_argument("AdjustWandBundle: sizes of cameras, active flags and wand poses disagree");
  }
  if (options.fixed_camera >= n || !active[options.fixed_camera]) {
    throw std::invalid_argument("AdjustWandBundle: the fixed camera must be active");
  }
  std::vector<std::array<double, kPoseSize>> poses(n);
  std::vector<std::array<double, kIntrinsicsSize>> intrinsics(n);
  for (size_t i = 0; i < n; ++i) {
    poses[i] = PoseBlock((*cameras)[i]);
    intrinsics[i] = IntrinsicsBlock((*cameras)[i].intrinsics);
  }

  // One loss object serves every residual; the problem must not delete it once per block.
  const std::unique_ptr<ceres::LossFunction> loss_owner(new ceres::HuberLoss(options.loss_scale_px));
  ceres::LossFunction* loss = loss_owner.get();
  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  std::vector<bool> used(n, false);
  std::vector<std::array<double, kWandPoseSize>> wand_blocks(frames.size());
  for (size_t f = 0; f < frames.size(); ++f) {
    const WandPose& pose = (*wand_poses)[f];
    double* block = wand_blocks[f].data();
    for (int i = 0; i < 3; ++i) {
      block[i] = pose.centre(i);
      block[3 + i] = pose.axis(i);
    }
    bool any = false;
    for (const WandView& view : frames[f].views) {
      if (!active[view.camera]) continue;
      for (size_t k = 0; k < view.pixels.size(); ++k) {
        problem.AddResidualBlock(WandReprojectionError::Create(view.pixels[k], wand.marker_offsets_mm[k]), loss,
                                       poses[view.camera].data(), intrinsics[view.camera].data(), block);
      }
      used[view.camera] = true;
      any = true;
    }
    if (any) problem.SetManifold(block, new WandPoseManifold());
  }
  std::vector<int> fixed_lens = {4, 5, 6, 7, 8};
  for (size_t i = 0; i < n; ++i) {
    if (!used[i]) continue;
    switch (options.refine_intrinsics) {
      case IntrinsicsRefinement::kNone:
        problem.SetParameterBlockConstant(intrinsics[i].data());
        break;
      case IntrinsicsRefinement::kFocalAndPrincipal:
        problem.SetManifold(intrinsics[i].data(), new ceres::SubsetManifold(kIntrinsicsSize, fixed_lens));
        break;
      case IntrinsicsRefinement::kAll:
        break;
    }
  }
  WandBundleSummary summary;
  if (!used[options.fixed_camera]) {
    summary.message = "the reference camera has no wand observations";
    return summary;
  }
  problem.SetParameterBlockConstant(poses[options.fixed_camera].data());

  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::DENSE_SCHUR;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.num_threads = options.num_threads;
  // Tight tolerances: the last hundredths of a degree live in the final iterations.
  solver_options.function_tolerance = 1e-10;
  solver_options.gradient_tolerance = 1e-12;
  solver_options.parameter_tolerance = 1e-10;
  ceres::Solver::Summary ceres_summary;
  ceres::Solve(solver_options, &problem, &ceres_summary);

  summary.usable = ceres_summary.IsSolutionUsable();
  summary.iterations = static_cast<int>(ceres_summary.iterations.size());
  summary.initial_cost = ceres_summary.initial_cost;
  summary.final_cost = ceres_summary.final_cost;
  summary.message = ceres_summary.BriefReport();
  if (!summary.usable) return summary;
  for (size_t f = 0; f < frames.size(); ++f) {
    const double* block = wand_blocks[f].data();
    (*wand_poses)[f].centre = Eigen::Vector3d(block[0], block[1], block[2]);
    (*wand_poses)[f].axis = Eigen::Vector3d(block[3], block[4], block[5]);
  }
  for (size_t i = 0; i < n; ++i) {
    if (!used[i]) continue;
    SetPoseFromBlock(poses[i].data(), &(*cameras)[i]);
    SetIntrinsicsFromBlock(intrinsics[i].data(), &(*cameras)[i].intrinsics);
  }
  return summary;
}

}  // namespace mocap
