// Joint-angle and segment-length errors against truth.
#include "skeleton/skeleton_eval.h"

#include <cmath>
#include <stdexcept>

namespace mocap {

SkeletonEvalReport EvaluateSkeleton(const Skeleton& truth, const SkeletonMotion& truth_motion, const Skeleton& estimate,
                                    const SkeletonMotion& estimate_motion) {
  if (truth.NumSegments() != estimate.NumSegments())
    throw std::invalid_argument("skeletons differ: " + std::to_string(truth.NumSegments()) + " and " +
                                std::to_string(estimate.NumSegments()) + " segments");
  for (size_t g = 0; g < truth.NumSegments(); ++g) {
    const SkeletonSegment &a = truth.segments[g], &b = estimate.segments[g];
    bool same = a.name == b.name && a.dofs.size() == b.dofs.size();
    for (size_t d = 0; same && d < a.dofs.size(); ++d) same = a.dofs[d].axis == b.dofs[d].axis;
    if (!same) throw std::invalid_argument("skeletons differ at segment " + std::to_string(g) + " (" + a.name + ", " + b.name + ")");
  }
  SkeletonEvalReport report;
  const size_t frames = std::min(truth_motion.poses.size(), estimate_motion.poses.size());
  for (size_t g = 1; g < truth.NumSegments(); ++g) {
    const SkeletonSegment& s = truth.segments[g];
    JointAngleError joint;
    joint.segment = s.name;
    const size_t first = truth.FirstDof(g);
    std::vector<double> sums(s.dofs.size(), 0.0);
    for (size_t f = 0; f < frames; ++f) {
      const auto& t = truth_motion.poses[f];
      const auto& e = estimate_motion.poses[f];
      if (t.empty() || e.empty()) continue;
      ++joint.frames;
      for (size_t d = 0; d < s.dofs.size(); ++d) {
        const double diff = std::remainder(e[first + d] - t[first + d], 2.0 * M_PI) * 180.0 / M_PI;
        sums[d] += diff * diff;
      }
    }
    double total = 0.0;
    for (double sum : sums) {
      joint.dof_rms_deg.push_back(joint.frames ? std::sqrt(sum / joint.frames) : NAN);
      total += sum;
    }
    joint.rms_deg = joint.frames ? std::sqrt(total / (joint.frames * s.dofs.size())) : NAN;
    report.joints.push_back(joint);
    SegmentLengthError length;
    length.segment = s.name;
    length.truth_mm = s.offset.norm();
    length.estimate_mm = estimate.segments[g].offset.norm();
    length.error_mm = length.estimate_mm - length.truth_mm;
    report.lengths.push_back(length);
  }
  return report;
}

}  // namespace mocap
