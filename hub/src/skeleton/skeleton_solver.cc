// Per-frame solve: one parameter block per segment (its angles; the root's with its translation),
// one residual block per marker over the blocks of its chain with an analytic Jacobian (a
// rotation moves a point by axis x (point - centre)), forward kinematics once per evaluation
// point (an evaluation callback) shared by all markers.
#include "skeleton/skeleton_solver.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>
#include <ceres/ceres.h>

#include "skeleton/kinematics.h"

namespace mocap {
namespace {

constexpr double kFreshStartLossScaleMm = 100.0;

// Forward kinematics once per evaluation point, shared by every marker: with an evaluation
// callback Ceres writes the point into the pose vector (the user's parameter memory) before it
// calls PrepareForEvaluation and then the cost functions.
class PoseKinematics : public ceres::EvaluationCallback {
 public:
  PoseKinematics(const Skeleton* skeleton, const double* pose) : skeleton_(skeleton), pose_(pose) {}
  void PrepareForEvaluation(bool /*evaluate_jacobians*/, bool new_evaluation_point) override {
    if (new_evaluation_point || !ready_) ForwardKinematics(*skeleton_, pose_, nullptr, &state_);
    ready_ = true;
  }
  const SkeletonPoseState& state() const { return state_; }

 private:
  const Skeleton* skeleton_;
  const double* pose_;
  bool ready_ = false;
  SkeletonPoseState state_;
};

// The pose parameters of segment g as one parameter block: the root's translation and angles,
// every other segment's angles (so a marker's Jacobian holds only the blocks of its chain).
size_t BlockStart(const Skeleton& skeleton, size_t g) { return g == 0 ? 0 : skeleton.FirstDof(g); }
size_t BlockSize(const Skeleton& skeleton, size_t g) {
  return skeleton.segments[g].dofs.size() + (g == 0 ? skeleton.FirstDof(0) : 0);
}

// One marker: its residual (the weighted offset from its observation) with the analytic Jacobian
// for each segment of its chain, root first.
class MarkerPoseCost : public ceres::CostFunction {
 public:
  MarkerPoseCost(const Skeleton* skeleton, int marker, std::vector<int> chain, const PoseKinematics* kinematics,
                 const Eigen::Vector3d* observed)
      : skeleton_(skeleton), marker_(marker), chain_(std::move(chain)), kinematics_(kinematics), observed_(observed),
        scale_(std::sqrt(skeleton->markers[marker].weight)) {
    set_num_residuals(3);
    for (int g : chain_) mutable_parameter_block_sizes()->push_back(static_cast<int>(BlockSize(*skeleton, g)));
  }

  bool Evaluate(double const* const* /*parameters*/, double* residuals, double** jacobians) const override {
    if (!observed_->allFinite()) {
      residuals[0] = residuals[1] = residuals[2] = 0.0;
      if (jacobians)
        for (size_t i = 0; i < chain_.size(); ++i)
          if (jacobians[i]) std::fill(jacobians[i], jacobians[i] + 3 * parameter_block_sizes()[i], 0.0);
      return true;
    }
    const SkeletonPoseState& state = kinematics_->state();
    const SkeletonMarker& m = skeleton_->markers[marker_];
    const Eigen::Vector3d p = MarkerInSkeleton(state, m.segment, m.offset);
    Eigen::Map<Eigen::Vector3d> residual(residuals);
    residual = scale_ * (p - *observed_);
    if (!jacobians) return true;
    for (size_t i = 0; i < chain_.size(); ++i) {
      double* j = jacobians[i];
      if (!j) continue;
      const size_t g = static_cast<size_t>(chain_[i]);
      const int cols = parameter_block_sizes()[i];
      const size_t start = BlockStart(*skeleton_, g);
      int c = 0;
      if (g == 0) {  // the root's translation
        std::fill(j, j + 3 * cols, 0.0);
        for (; c < 3; ++c) j[c * cols + c] = scale_;
      }
      for (; c < cols; ++c) {
        const size_t k = start + static_cast<size_t>(c);
        const Eigen::Vector3d d = scale_ * state.axis[k].cross(p - state.origin[state.dof_segment[k]]);
        for (int r = 0; r < 3; ++r) j[r * cols + c] = d[r];
      }
    }
    return true;
  }

 private:
  const Skeleton* skeleton_;
  int marker_;
  std::vector<int> chain_;
  const PoseKinematics* kinematics_;
  const Eigen::Vector3d* observed_;
  double scale_;
};

ceres::Problem::Options ProblemOptions(ceres::EvaluationCallback* callback) {
  ceres::Problem::Options o;
  o.evaluation_callback = callback;
  return o;
}

}  // namespace

void SkeletonSolveOptions::Check() const {
  if (!(loss_scale_mm > 0.0 && loss_scale_mm <= 1000.0))
    throw std::invalid_argument("loss_scale_mm: " + std::to_string(loss_scale_mm) + " not in (0, 1000]");
  if (max_iterations < 1 || max_iterations > 1000)
    throw std::invalid_argument("max_iterations: " + std::to_string(max_iterations) + " not in 1..1000");
  if (warm_iterations < 1 || warm_iterations > max_iterations)
    throw std::invalid_argument("warm_iterations: " + std::to_string(warm_iterations) + " not in 1..max_iterations (" +
                                std::to_string(max_iterations) + ")");
  if (!(restart_median_mm > 0.0)) throw std::invalid_argument("restart_median_mm: must be > 0");
  if (min_markers < 3) throw std::invalid_argument("min_markers: " + std::to_string(min_markers) + " is below 3");
}

Eigen::Vector3d EulerFromRotation(const Eigen::Matrix3d& r, int i, int j, int k) {
  if (i == k) throw std::invalid_argument("EulerFromRotation: three distinct axes are needed");
  // An even permutation of (x, y, z) gives sin(b) = r(i, k); an odd one its negative.
  const double sign = ((j - i + 3) % 3 == 1) ? 1.0 : -1.0;
  const double sb = std::max(-1.0, std::min(1.0, sign * r(i, k)));
  const double b = std::asin(sb);
  const double a = std::atan2(-sign * r(j, k), r(k, k));
  const double c = std::atan2(-sign * r(i, j), r(i, i));
  return {a, b, c};
}

bool InitialRootPose(const Skeleton& skeleton, const std::vector<Eigen::Vector3d>& observed, std::vector<double>* pose) {
  pose->assign(skeleton.NumPoseParameters(), 0.0);
  SkeletonPoseState rest;
  ForwardKinematics(skeleton, pose->data(), nullptr, &rest);
  std::vector<int> root, all;
  for (size_t m = 0; m < skeleton.markers.size(); ++m) {
    if (!observed[m].allFinite()) continue;
    all.push_back(static_cast<int>(m));
    if (skeleton.markers[m].segment == 0) root.push_back(static_cast<int>(m));
  }
  const std::vector<int>& use = root.size() >= 3 ? root : all;
  if (use.size() < 3) return false;
  Eigen::Matrix3Xd from(3, use.size()), to(3, use.size());
  for (size_t i = 0; i < use.size(); ++i) {
    const SkeletonMarker& m = skeleton.markers[use[i]];
    from.col(i) = MarkerInSkeleton(rest, m.segment, m.offset);
    to.col(i) = observed[use[i]];
  }
  const Eigen::Matrix4d t = Eigen::umeyama(from, to, false);
  if (!t.allFinite()) return false;
  const auto& dofs = skeleton.segments[0].dofs;
  const Eigen::Vector3d angles = EulerFromRotation(t.block<3, 3>(0, 0), dofs[0].axis, dofs[1].axis, dofs[2].axis);
  for (int i = 0; i < 3; ++i) {
    (*pose)[i] = t(i, 3);
    (*pose)[3 + i] = angles[i];
  }
  return true;
}

struct SkeletonSolver::Impl {
  Skeleton skeleton;
  SkeletonSolveOptions options;
  std::vector<Eigen::Vector3d> observed;
  std::vector<double> pose;
  PoseKinematics kinematics;
  ceres::Problem problem;
  ceres::LossFunctionWrapper* loss = nullptr;  // owned by the problem
  ceres::Solver::Options solver_options;
  SkeletonPoseState state;
  std::vector<double> seen;  // scratch: the residuals of the markers seen

  Impl(const Skeleton& s, const SkeletonSolveOptions& o)
      : skeleton(s), options(o), observed(s.markers.size(), Eigen::Vector3d::Constant(NAN)),
        pose(s.NumPoseParameters(), 0.0), kinematics(&skeleton, pose.data()), problem(ProblemOptions(&kinematics)) {}
};

SkeletonSolver::SkeletonSolver(const Skeleton& skeleton, const SkeletonSolveOptions& options)
    : impl_(std::make_unique<Impl>(skeleton, options)) {
  options.Check();
  skeleton.Check();
  Impl& s = *impl_;
  const auto chains = SegmentChains(s.skeleton);
  for (size_t g = 0; g < s.skeleton.NumSegments(); ++g)
    s.problem.AddParameterBlock(s.pose.data() + BlockStart(s.skeleton, g), static_cast<int>(BlockSize(s.skeleton, g)));
  s.loss = new ceres::LossFunctionWrapper(new ceres::CauchyLoss(options.loss_scale_mm), ceres::TAKE_OWNERSHIP);
  for (size_t m = 0; m < s.skeleton.markers.size(); ++m) {
    const std::vector<int>& chain = chains[s.skeleton.markers[m].segment];
    std::vector<double*> blocks;
    for (int g : chain) blocks.push_back(s.pose.data() + BlockStart(s.skeleton, static_cast<size_t>(g)));
    s.problem.AddResidualBlock(new MarkerPoseCost(&s.skeleton, static_cast<int>(m), chain, &s.kinematics, &s.observed[m]),
                               s.loss, blocks);
  }
  std::vector<double> lower, upper;
  PoseBounds(s.skeleton, &lower, &upper);
  for (size_t g = 0; g < s.skeleton.NumSegments(); ++g) {
    const size_t start = BlockStart(s.skeleton, g);
    double* block = s.pose.data() + start;
    for (size_t c = 0; c < BlockSize(s.skeleton, g); ++c) {
      if (std::isfinite(lower[start + c])) s.problem.SetParameterLowerBound(block, static_cast<int>(c), lower[start + c]);
      if (std::isfinite(upper[start + c])) s.problem.SetParameterUpperBound(block, static_cast<int>(c), upper[start + c]);
    }
  }
  s.solver_options.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
  s.solver_options.max_num_iterations = options.max_iterations;
  s.solver_options.num_threads = 1;
  s.solver_options.logging_type = ceres::SILENT;
  s.solver_options.function_tolerance = 1e-7;
  s.solver_options.parameter_tolerance = 1e-7;
}

SkeletonSolver::~SkeletonSolver() = default;

bool SkeletonSolver::FreshStart() {
  Impl& s = *impl_;
  if (!InitialRootPose(s.skeleton, s.observed, &s.pose)) return false;
  // From the rest pose every marker may be far off: a convex loss first brings the limbs near,
  // then the solve proper (Cauchy) can tell outliers from markers still on their way.
  s.loss->Reset(new ceres::HuberLoss(kFreshStartLossScaleMm), ceres::TAKE_OWNERSHIP);
  ceres::Solver::Summary summary;
  ceres::Solve(s.solver_options, &s.problem, &summary);
  s.loss->Reset(new ceres::CauchyLoss(s.options.loss_scale_mm), ceres::TAKE_OWNERSHIP);
  return true;
}

void SkeletonSolver::RunSolver(SkeletonFrameFit* fit) {
  Impl& s = *impl_;
  ceres::Solver::Summary summary;
  ceres::Solve(s.solver_options, &s.problem, &summary);
  fit->iterations += static_cast<int>(summary.iterations.size());
  ForwardKinematics(s.skeleton, s.pose.data(), nullptr, &s.state);
  fit->pose = s.pose;
  fit->residual_mm.assign(s.skeleton.markers.size(), NAN);
  double sum = 0.0;
  fit->max_mm = 0.0;
  for (size_t m = 0; m < s.skeleton.markers.size(); ++m) {
    if (!s.observed[m].allFinite()) continue;
    const SkeletonMarker& marker = s.skeleton.markers[m];
    const double d = (MarkerInSkeleton(s.state, marker.segment, marker.offset) - s.observed[m]).norm();
    fit->residual_mm[m] = d;
    sum += d * d;
    fit->max_mm = std::max(fit->max_mm, d);
  }
  fit->rms_mm = fit->markers > 0 ? std::sqrt(sum / fit->markers) : 0.0;
  s.seen.clear();
  for (double r : fit->residual_mm)
    if (std::isfinite(r)) s.seen.push_back(r);
  if (!s.seen.empty()) {
    std::nth_element(s.seen.begin(), s.seen.begin() + static_cast<long>(s.seen.size() / 2), s.seen.end());
    fit->median_mm = s.seen[s.seen.size() / 2];
  }
  fit->solved = summary.IsSolutionUsable();
}

SkeletonFrameFit SkeletonSolver::Solve(const std::vector<Eigen::Vector3d>& observed) {
  Impl& s = *impl_;
  if (observed.size() != s.skeleton.markers.size())
    throw std::invalid_argument("SkeletonSolver::Solve: " + std::to_string(observed.size()) + " points for " +
                                std::to_string(s.skeleton.markers.size()) + " markers");
  SkeletonFrameFit fit;
  for (size_t m = 0; m < observed.size(); ++m) {
    s.observed[m] = observed[m];
    if (observed[m].allFinite()) ++fit.markers;
  }
  if (fit.markers < s.options.min_markers) {
    has_previous_ = false;
    fit.residual_mm.assign(observed.size(), NAN);
    return fit;
  }
  const bool warm = has_previous_;
  if (!warm && !FreshStart()) {
    fit.residual_mm.assign(observed.size(), NAN);
    return fit;
  }
  const std::vector<double> start = s.pose;
  s.solver_options.max_num_iterations = warm ? s.options.warm_iterations : s.options.max_iterations;
  RunSolver(&fit);
  s.solver_options.max_num_iterations = s.options.max_iterations;
  if (warm && (!fit.solved || fit.median_mm > s.options.restart_median_mm)) {
    SkeletonFrameFit fresh;
    fresh.markers = fit.markers;
    fresh.iterations = fit.iterations;
    if (FreshStart()) {
      RunSolver(&fresh);
      fresh.restarted = true;
      if (fresh.solved && (!fit.solved || fresh.median_mm < fit.median_mm)) fit = fresh;
    }
    s.pose = fit.pose;
  }
  has_previous_ = fit.solved;
  if (!fit.solved) s.pose = start;
  return fit;
}

}  // namespace mocap
