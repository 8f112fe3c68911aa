// Subject calibration: scale, track, then one joint fit of poses, joint offsets and marker offsets.
#include "skeleton/subject_calibration.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

#include <Eigen/Geometry>
#include <ceres/ceres.h>

#include "skeleton/kinematics.h"
#include "skeleton/skeleton_solver.h"

namespace mocap {
namespace {

constexpr double kFreeCentreSigmaMm = 200.0;  // a moving joint's centre: only keeps the fit posed
constexpr double kHeldCentreSigmaMm = 2.0;    // a still joint's centre stays at the scaled template's
constexpr double kMarkerOffsetSigmaMm = 300.0;
constexpr double kReferenceZeroWeight = 2000.0;  // residual mm per radian at the reference frame
constexpr double kLossScaleMm = 10.0;

// One marker in one frame; parameter blocks: the frame's pose, the offset of every segment of
// the marker's chain below the root (a bone's length or a 3-D offset), the marker's offset.
class MarkerCalibrationCost : public ceres::CostFunction {
 public:
  MarkerCalibrationCost(const Skeleton* skeleton, const std::vector<Eigen::Vector3d>* bone_dirs,
                        std::vector<int> chain, std::vector<int> chain_dofs, const Eigen::Vector3d& observed)
      : skeleton_(skeleton), bone_dirs_(bone_dirs), chain_(std::move(chain)),
        chain_dofs_(std::move(chain_dofs)), observed_(observed) {
    set_num_residuals(3);
    mutable_parameter_block_sizes()->push_back(static_cast<int>(skeleton->NumPoseParameters()));
    for (size_t i = 1; i < chain_.size(); ++i)
      mutable_parameter_block_sizes()->push_back(skeleton->segments[chain_[i]].bone ? 1 : 3);
    mutable_parameter_block_sizes()->push_back(3);
  }

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    thread_local std::vector<Eigen::Vector3d> offsets;
    thread_local SkeletonPoseState state;
    offsets.resize(skeleton_->NumSegments());
    for (size_t g = 0; g < offsets.size(); ++g) offsets[g] = skeleton_->segments[g].offset;
    for (size_t i = 1; i < chain_.size(); ++i) {
      const int g = chain_[i];
      offsets[g] = skeleton_->segments[g].bone ? Eigen::Vector3d((*bone_dirs_)[g] * parameters[i][0])
                                               : Eigen::Vector3d(parameters[i][0], parameters[i][1], parameters[i][2]);
    }
    ForwardKinematics(*skeleton_, parameters[0], offsets.data(), &state);
    const int s = chain_.back();
    const Eigen::Map<const Eigen::Vector3d> c(parameters[chain_.size()]);
    const Eigen::Vector3d p = state.origin[s] + state.rotation[s] * c;
    Eigen::Map<Eigen::Vector3d> residual(residuals);
    residual = p - observed_;
    if (!jacobians) return true;
    const int n = parameter_block_sizes()[0];
    if (jacobians[0]) {
      double* j = jacobians[0];
      std::fill(j, j + 3 * n, 0.0);
      for (int r = 0; r < 3; ++r) j[r * n + r] = 1.0;
      for (int k : chain_dofs_) {
        const Eigen::Vector3d d = state.axis[k].cross(p - state.origin[state.dof_segment[k]]);
        for (int r = 0; r < 3; ++r) j[r * n + k] = d[r];
      }
    }
    for (size_t i = 1; i < chain_.size(); ++i) {
      if (!jacobians[i]) continue;
      const int g = chain_[i];
      const Eigen::Matrix3d& parent = state.rotation[skeleton_->segments[g].parent];
      if (skeleton_->segments[g].bone) {
        const Eigen::Vector3d d = parent * (*bone_dirs_)[g];
        for (int r = 0; r < 3; ++r) jacobians[i][r] = d[r];
      } else {
        Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> j(jacobians[i]);
        j = parent;
      }
    }
    if (jacobians[chain_.size()]) {
      Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> j(jacobians[chain_.size()]);
      j = state.rotation[s];
    }
    return true;
  }

 private:
  const Skeleton* skeleton_;
  const std::vector<Eigen::Vector3d>* bone_dirs_;
  std::vector<int> chain_, chain_dofs_;
  Eigen::Vector3d observed_;
};

// (x - target) / sigma for a whole block, or weight * x[k] for chosen entries of it.
class PriorCost : public ceres::CostFunction {
 public:
  PriorCost(std::vector<double> target, std::vector<int> entries, int block_size, double weight)
      : target_(std::move(target)), entries_(std::move(entries)), weight_(weight) {
    set_num_residuals(static_cast<int>(entries_.size()));
    mutable_parameter_block_sizes()->push_back(block_size);
  }
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const int n = parameter_block_sizes()[0];
    for (size_t r = 0; r < entries_.size(); ++r) residuals[r] = weight_ * (parameters[0][entries_[r]] - target_[r]);
    if (jacobians && jacobians[0]) {
      std::fill(jacobians[0], jacobians[0] + entries_.size() * n, 0.0);
      for (size_t r = 0; r < entries_.size(); ++r) jacobians[0][r * n + entries_[r]] = weight_;
    }
    return true;
  }

 private:
  std::vector<double> target_;
  std::vector<int> entries_;
  double weight_;
};

double RotationAngleDeg(const Eigen::Matrix3d& r) {
  return Eigen::AngleAxisd(r).angle() * 180.0 / M_PI;
}

// Rest-pose height of the template's markers and the subject's median height in the window.
double HeightScale(const Skeleton& skeleton, const MarkerTrajectories& markers, const std::vector<int>& columns,
                   const std::vector<size_t>& frames) {
  std::vector<double> rest_pose(skeleton.NumPoseParameters(), 0.0);
  SkeletonPoseState rest;
  ForwardKinematics(skeleton, rest_pose.data(), nullptr, &rest);
  double lo = INFINITY, hi = -INFINITY;
  for (const SkeletonMarker& m : skeleton.markers) {
    const double y = MarkerInSkeleton(rest, m.segment, m.offset).y();
    lo = std::min(lo, y);
    hi = std::max(hi, y);
  }
  std::vector<double> heights;
  for (size_t f : frames) {
    double flo = INFINITY, fhi = -INFINITY;
    int seen = 0;
    for (size_t m = 0; m < columns.size(); ++m) {
      if (columns[m] < 0 || !markers.Has(f, columns[m])) continue;
      flo = std::min(flo, markers.At(f, columns[m]).y());
      fhi = std::max(fhi, markers.At(f, columns[m]).y());
      ++seen;
    }
    if (seen * 10 >= static_cast<int>(columns.size()) * 8) heights.push_back(fhi - flo);
  }
  if (heights.empty() || hi - lo < 1.0) return 1.0;
  std::nth_element(heights.begin(), heights.begin() + heights.size() / 2, heights.end());
  return std::max(0.5, std::min(2.0, heights[heights.size() / 2] / (hi - lo)));
}

Skeleton Scaled(const Skeleton& skeleton, double scale) {
  Skeleton out = skeleton;
  for (SkeletonSegment& s : out.segments) {
    s.offset *= scale;
    s.end *= scale;
  }
  for (SkeletonMarker& m : out.markers) m.offset *= scale;
  return out;
}

// Every frame of the window solved in order with `skeleton`, warm-started; poses of the solved ones.
std::vector<std::pair<size_t, std::vector<double>>> TrackWindow(const Skeleton& skeleton,
                                                                const MarkerTrajectories& markers,
                                                                const std::vector<int>& columns,
                                                                const std::vector<size_t>& window) {
  SkeletonSolver solver(skeleton, SkeletonSolveOptions{});
  std::vector<std::pair<size_t, std::vector<double>>> poses;
  for (size_t f : window) {
    const SkeletonFrameFit fit = solver.Solve(FrameObservations(markers, columns, f));
    if (fit.solved) poses.emplace_back(f, fit.pose);
  }
  return poses;
}

}  // namespace

void SubjectCalibrationOptions::Check() const {
  if (!(start_s >= 0.0 && start_s < 1e6)) throw std::invalid_argument("start_s: " + std::to_string(start_s) + " not >= 0");
  if (!(duration_s > 0.0 && duration_s <= 600.0))
    throw std::invalid_argument("duration_s: " + std::to_string(duration_s) + " not in (0, 600]");
  if (max_frames < 5 || max_frames > 2000)
    throw std::invalid_argument("max_frames: " + std::to_string(max_frames) + " not in 5..2000");
  if (!(min_joint_range_deg >= 0.0 && min_joint_range_deg <= 90.0))
    throw std::invalid_argument("min_joint_range_deg: " + std::to_string(min_joint_range_deg) + " not in 0..90");
}

std::vector<int> MarkerColumns(const Skeleton& skeleton, const MarkerTrajectories& markers) {
  std::vector<int> columns(skeleton.markers.size(), -1);
  for (size_t m = 0; m < skeleton.markers.size(); ++m)
    for (size_t c = 0; c < markers.names.size(); ++c)
      if (markers.names[c] == skeleton.markers[m].name) columns[m] = static_cast<int>(c);
  return columns;
}

std::vector<Eigen::Vector3d> FrameObservations(const MarkerTrajectories& markers, const std::vector<int>& columns,
                                               size_t frame) {
  std::vector<Eigen::Vector3d> observed(columns.size(), MarkerTrajectories::Gap());
  for (size_t m = 0; m < columns.size(); ++m)
    if (columns[m] >= 0) observed[m] = markers.At(frame, columns[m]);
  return observed;
}

namespace {

using TrackedPoses = std::vector<std::pair<size_t, std::vector<double>>>;

// The joint fit's parameter blocks: the picked frames' poses, each segment's offset below the
// root (a bone's length or a 3-D offset) and each marker's offset on its segment.
struct JointFitParameters {
  std::vector<std::vector<double>> poses, offsets, marker_offsets;
};

// CalibrateSubject's stages. Round 0 holds every joint centre at the scaled template's and fits
// the marker offsets only: tracking with the raw template is too rough to tell a still joint
// from a moving one (it showed 10-17 deg of spurious turning at standing legs). Round 1 tracks
// with that skeleton and measures each joint's range; rounds 1 and 2 free the centres of the
// joints that turned.
class SubjectCalibrator {
 public:
  SubjectCalibrator(const Skeleton& skeleton_template, const MarkerTrajectories& markers,
                    const SubjectCalibrationOptions& options);
  SubjectCalibration Run();

 private:
  void SelectWindow();
  // Frames for the joint fit: evenly spread over the tracked ones; the first is the reference.
  std::vector<size_t> PickFrames(size_t tracked) const;
  // Each joint's range over the picked frames decides whether the trial finds its centre.
  void MeasureJointRanges(const TrackedPoses& tracked, const std::vector<size_t>& pick);
  void FitRound(const TrackedPoses& tracked, const std::vector<size_t>& pick);
  JointFitParameters InitialParameters(const TrackedPoses& tracked, const std::vector<size_t>& pick) const;
  void AddMarkerCosts(ceres::Problem* problem, JointFitParameters* fit, const TrackedPoses& tracked,
                      const std::vector<size_t>& pick) const;
  void AddPriors(ceres::Problem* problem, JointFitParameters* fit) const;
  void Solve(ceres::Problem* problem, JointFitParameters* fit) const;
  void MeasureResiduals(const JointFitParameters& fit, const TrackedPoses& tracked, const std::vector<size_t>& pick);

  const MarkerTrajectories& markers_;
  const SubjectCalibrationOptions& options_;
  const std::vector<int> columns_;
  std::vector<size_t> window_;
  SubjectCalibration result_;
  Skeleton scaled_template_, skeleton_;
  std::vector<std::vector<int>> chains_;
  std::vector<Eigen::Vector3d> bone_dirs_;
  std::vector<bool> held_;
};

SubjectCalibrator::SubjectCalibrator(const Skeleton& skeleton_template, const MarkerTrajectories& markers,
                                     const SubjectCalibrationOptions& options)
    : markers_(markers), options_((options.Check(), options)),
      columns_((skeleton_template.Check(), MarkerColumns(skeleton_template, markers))) {
  if (markers.NumFrames() == 0 || !(markers.rate_hz > 0.0)) throw std::invalid_argument("trial: no frames");
  SelectWindow();
  for (size_t m = 0; m < columns_.size(); ++m) {
    bool seen = false;
    for (size_t f : window_) seen = seen || (columns_[m] >= 0 && markers.Has(f, columns_[m]));
    if (!seen)
      throw std::invalid_argument("marker " + skeleton_template.markers[m].name +
                                  (columns_[m] < 0 ? " is not in the trial" : " is never seen in the window") +
                                  ": its offset cannot be calibrated");
  }
  result_.scale = HeightScale(skeleton_template, markers, columns_, window_);
  scaled_template_ = Scaled(skeleton_template, result_.scale);
  skeleton_ = scaled_template_;
  chains_ = SegmentChains(skeleton_);
  bone_dirs_.assign(skeleton_.NumSegments(), Eigen::Vector3d::Zero());
  for (size_t g = 0; g < skeleton_.NumSegments(); ++g)
    if (skeleton_.segments[g].bone) bone_dirs_[g] = skeleton_.segments[g].offset.normalized();
  held_.assign(skeleton_.NumSegments(), true);
}

void SubjectCalibrator::SelectWindow() {
  const double t0 = markers_.TimeOf(0) + options_.start_s;
  for (size_t f = 0; f < markers_.NumFrames(); ++f) {
    const double t = markers_.TimeOf(f);
    if (t >= t0 - 1e-9 && t < t0 + options_.duration_s - 1e-9) window_.push_back(f);
  }
  if (window_.size() < 5)
    throw std::invalid_argument("trial: " + std::to_string(window_.size()) + " frames in the window from " +
                                std::to_string(options_.start_s) + " s for " + std::to_string(options_.duration_s) +
                                " s (at least 5 needed)");
}

SubjectCalibration SubjectCalibrator::Run() {
  for (int round = 0; round < 3; ++round) {
    const TrackedPoses tracked = TrackWindow(skeleton_, markers_, columns_, window_);
    if (tracked.size() < 5)
      throw std::invalid_argument("trial: only " + std::to_string(tracked.size()) +
                                  " frames of the window could be posed with the template");
    const std::vector<size_t> pick = PickFrames(tracked.size());
    if (round == 1) MeasureJointRanges(tracked, pick);
    FitRound(tracked, pick);
  }
  for (JointCalibration& joint : result_.joints)
    joint.length_mm = skeleton_.segments[skeleton_.FindSegment(joint.segment)].offset.norm();
  skeleton_.calibrated = true;
  result_.skeleton = skeleton_;
  return result_;
}

std::vector<size_t> SubjectCalibrator::PickFrames(size_t tracked) const {
  std::vector<size_t> pick;
  const size_t k = std::min<size_t>(options_.max_frames, tracked);
  for (size_t i = 0; i < k; ++i) pick.push_back(i * (tracked - 1) / std::max<size_t>(1, k - 1));
  pick.erase(std::unique(pick.begin(), pick.end()), pick.end());
  return pick;
}

void SubjectCalibrator::MeasureJointRanges(const TrackedPoses& tracked, const std::vector<size_t>& pick) {
  std::vector<SkeletonPoseState> states(pick.size());
  for (size_t i = 0; i < pick.size(); ++i)
    ForwardKinematics(skeleton_, tracked[pick[i]].second.data(), nullptr, &states[i]);
  result_.joints.clear();
  std::vector<std::string> still;
  for (size_t g = 1; g < skeleton_.NumSegments(); ++g) {
    const int p = skeleton_.segments[g].parent;
    double range = 0.0;
    for (size_t a = 0; a < states.size(); ++a)
      for (size_t b = a + 1; b < states.size(); ++b) {
        const Eigen::Matrix3d ra = states[a].rotation[p].transpose() * states[a].rotation[g];
        const Eigen::Matrix3d rb = states[b].rotation[p].transpose() * states[b].rotation[g];
        range = std::max(range, RotationAngleDeg(ra.transpose() * rb));
      }
    JointCalibration joint;
    joint.segment = skeleton_.segments[g].name;
    joint.range_deg = range;
    joint.functional = range >= options_.min_joint_range_deg;
    held_[g] = !joint.functional;
    if (held_[g]) still.push_back(joint.segment + " (" + std::to_string(static_cast<int>(std::round(range))) + " deg)");
    result_.joints.push_back(joint);
  }
  if (!still.empty() && !options_.keep_template_centres) {
    std::string list;
    for (const std::string& s : still) list += (list.empty() ? "" : ", ") + s;
    throw std::invalid_argument("joints turning less than " + std::to_string(options_.min_joint_range_deg) +
                                " deg in the window, whose centres the trial cannot determine: " + list +
                                " (use a range-of-motion trial, or keep the template's centres)");
  }
}

JointFitParameters SubjectCalibrator::InitialParameters(const TrackedPoses& tracked,
                                                        const std::vector<size_t>& pick) const {
  JointFitParameters fit;
  for (size_t i : pick) fit.poses.push_back(tracked[i].second);
  fit.offsets.resize(skeleton_.NumSegments());
  for (size_t g = 1; g < skeleton_.NumSegments(); ++g) {
    const SkeletonSegment& s = skeleton_.segments[g];
    if (s.bone)
      fit.offsets[g] = {s.offset.norm()};
    else
      fit.offsets[g] = {s.offset.x(), s.offset.y(), s.offset.z()};
  }
  for (const SkeletonMarker& m : skeleton_.markers) fit.marker_offsets.push_back({m.offset.x(), m.offset.y(), m.offset.z()});
  return fit;
}

void SubjectCalibrator::FitRound(const TrackedPoses& tracked, const std::vector<size_t>& pick) {
  JointFitParameters fit = InitialParameters(tracked, pick);
  ceres::Problem problem;  // owns the costs and the one loss they share
  AddMarkerCosts(&problem, &fit, tracked, pick);
  AddPriors(&problem, &fit);
  Solve(&problem, &fit);
  for (size_t g = 1; g < skeleton_.NumSegments(); ++g) {
    SkeletonSegment& s = skeleton_.segments[g];
    s.offset = s.bone ? Eigen::Vector3d(bone_dirs_[g] * fit.offsets[g][0])
                      : Eigen::Vector3d(fit.offsets[g][0], fit.offsets[g][1], fit.offsets[g][2]);
  }
  for (size_t m = 0; m < skeleton_.markers.size(); ++m)
    skeleton_.markers[m].offset = Eigen::Vector3d(fit.marker_offsets[m][0], fit.marker_offsets[m][1], fit.marker_offsets[m][2]);
  MeasureResiduals(fit, tracked, pick);
}

void SubjectCalibrator::AddMarkerCosts(ceres::Problem* problem, JointFitParameters* fit, const TrackedPoses& tracked,
                                       const std::vector<size_t>& pick) const {
  std::vector<double> lower, upper;
  PoseBounds(skeleton_, &lower, &upper);
  auto* loss = new ceres::HuberLoss(kLossScaleMm);
  for (size_t i = 0; i < fit->poses.size(); ++i) {
    const size_t f = tracked[pick[i]].first;
    for (size_t m = 0; m < skeleton_.markers.size(); ++m) {
      if (columns_[m] < 0 || !markers_.Has(f, columns_[m])) continue;
      const int s = skeleton_.markers[m].segment;
      std::vector<int> chain_dofs;
      std::vector<double*> blocks = {fit->poses[i].data()};
      for (int g : chains_[s]) {
        const size_t first = skeleton_.FirstDof(g);
        for (size_t d = 0; d < skeleton_.segments[g].dofs.size(); ++d) chain_dofs.push_back(static_cast<int>(first + d));
        if (g != 0) blocks.push_back(fit->offsets[g].data());
      }
      blocks.push_back(fit->marker_offsets[m].data());
      problem->AddResidualBlock(new MarkerCalibrationCost(&skeleton_, &bone_dirs_, chains_[s], chain_dofs,
                                                          markers_.At(f, columns_[m])),
                                loss, blocks);
    }
    for (size_t k = 0; k < skeleton_.NumPoseParameters(); ++k) {
      if (std::isfinite(lower[k])) problem->SetParameterLowerBound(fit->poses[i].data(), static_cast<int>(k), lower[k]);
      if (std::isfinite(upper[k])) problem->SetParameterUpperBound(fit->poses[i].data(), static_cast<int>(k), upper[k]);
    }
  }
}

void SubjectCalibrator::AddPriors(ceres::Problem* problem, JointFitParameters* fit) const {
  const size_t n_seg = skeleton_.NumSegments();
  // Gauge: reference_zero segments' angles are zero in the reference (first picked) frame.
  std::vector<int> zero_entries;
  for (size_t g = 0; g < n_seg; ++g) {
    if (!skeleton_.segments[g].reference_zero) continue;
    const size_t first = skeleton_.FirstDof(g);
    for (size_t d = 0; d < skeleton_.segments[g].dofs.size(); ++d)
      if (g != 0 || skeleton_.segments[g].dofs[d].axis != 1) zero_entries.push_back(static_cast<int>(first + d));
  }
  if (!zero_entries.empty())
    problem->AddResidualBlock(new PriorCost(std::vector<double>(zero_entries.size(), 0.0), zero_entries,
                                            static_cast<int>(skeleton_.NumPoseParameters()), kReferenceZeroWeight),
                              nullptr, fit->poses[0].data());
  for (size_t g = 1; g < n_seg; ++g) {
    if (!problem->HasParameterBlock(fit->offsets[g].data())) continue;
    const SkeletonSegment& s = scaled_template_.segments[g];
    std::vector<double> target = skeleton_.segments[g].bone ? std::vector<double>{s.offset.norm()}
                                                            : std::vector<double>{s.offset.x(), s.offset.y(), s.offset.z()};
    // A hinge's centre can slide along its axis without changing any marker's path: that
    // component stays at the scaled template's like a still joint's centre.
    const int hinge_axis = !s.bone && s.dofs.size() == 1 ? s.dofs[0].axis : -1;
    std::vector<int> free_entries, held_entries;
    std::vector<double> free_target, held_target;
    for (size_t e = 0; e < target.size(); ++e) {
      const bool hold = held_[g] || static_cast<int>(e) == hinge_axis;
      (hold ? held_entries : free_entries).push_back(static_cast<int>(e));
      (hold ? held_target : free_target).push_back(target[e]);
    }
    const int size = static_cast<int>(target.size());
    if (!free_entries.empty())
      problem->AddResidualBlock(new PriorCost(free_target, free_entries, size, 1.0 / kFreeCentreSigmaMm), nullptr,
                                fit->offsets[g].data());
    if (!held_entries.empty())
      problem->AddResidualBlock(new PriorCost(held_target, held_entries, size, 1.0 / kHeldCentreSigmaMm), nullptr,
                                fit->offsets[g].data());
  }
  for (size_t m = 0; m < skeleton_.markers.size(); ++m) {
    if (!problem->HasParameterBlock(fit->marker_offsets[m].data())) continue;
    problem->AddResidualBlock(new PriorCost(fit->marker_offsets[m], {0, 1, 2}, 3, 1.0 / kMarkerOffsetSigmaMm), nullptr,
                              fit->marker_offsets[m].data());
  }
}

void SubjectCalibrator::Solve(ceres::Problem* problem, JointFitParameters* fit) const {
  ceres::Solver::Options solver_options;
  // No marker residual holds two frames' poses: they are eliminated frame by frame (Schur), leaving
  // a small dense system in the offsets.
  solver_options.linear_solver_type = ceres::DENSE_SCHUR;
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
  for (auto& pose : fit->poses) ordering->AddElementToGroup(pose.data(), 0);
  for (size_t g = 1; g < skeleton_.NumSegments(); ++g)
    if (problem->HasParameterBlock(fit->offsets[g].data())) ordering->AddElementToGroup(fit->offsets[g].data(), 1);
  for (auto& m : fit->marker_offsets)
    if (problem->HasParameterBlock(m.data())) ordering->AddElementToGroup(m.data(), 1);
  solver_options.linear_solver_ordering = ordering;
  solver_options.max_num_iterations = 100;
  solver_options.num_threads = 1;
  solver_options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, problem, &summary);
  if (!summary.IsSolutionUsable()) throw std::invalid_argument("calibration fit failed: " + summary.message);
}

void SubjectCalibrator::MeasureResiduals(const JointFitParameters& fit, const TrackedPoses& tracked,
                                         const std::vector<size_t>& pick) {
  double sum = 0.0;
  int count = 0;
  result_.max_mm = 0.0;
  SkeletonPoseState state;
  for (size_t i = 0; i < fit.poses.size(); ++i) {
    ForwardKinematics(skeleton_, fit.poses[i].data(), nullptr, &state);
    const size_t f = tracked[pick[i]].first;
    for (size_t m = 0; m < skeleton_.markers.size(); ++m) {
      if (columns_[m] < 0 || !markers_.Has(f, columns_[m])) continue;
      const double d = (MarkerInSkeleton(state, skeleton_.markers[m].segment, skeleton_.markers[m].offset) -
                        markers_.At(f, columns_[m])).norm();
      sum += d * d;
      ++count;
      result_.max_mm = std::max(result_.max_mm, d);
    }
  }
  result_.rms_mm = count ? std::sqrt(sum / count) : 0.0;
  result_.frames_used = static_cast<int>(fit.poses.size());
}

}  // namespace

SubjectCalibration CalibrateSubject(const Skeleton& skeleton_template, const MarkerTrajectories& markers,
                                    const SubjectCalibrationOptions& options) {
  return SubjectCalibrator(skeleton_template, markers, options).Run();
}

}  // namespace mocap
