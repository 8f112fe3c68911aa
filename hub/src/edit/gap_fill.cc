// The five fill methods (see gap_fill.h). Time is the frame number, so a take with skipped frame
// numbers is interpolated at the right instants.
#include "edit/gap_fill.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <stdexcept>

#include <Eigen/Geometry>

#include "geometry/rigid_fit.h"

namespace mocap::edit {
namespace {

struct Gap {
  size_t first = 0, last = 0;  // frame indices of the missing run
  long before = -1, after = -1;  // bounding measured frame indices, -1: none
};

std::vector<Gap> GapsOf(const EditedTake& take, size_t marker, size_t first, size_t last) {
  std::vector<Gap> gaps;
  const size_t frames = take.markers.NumFrames();
  size_t f = 0;
  while (f < frames) {
    if (take.markers.Has(f, marker)) {
      ++f;
      continue;
    }
    Gap gap;
    gap.first = f;
    while (f < frames && !take.markers.Has(f, marker)) ++f;
    gap.last = f - 1;
    gap.before = gap.first > 0 ? static_cast<long>(gap.first) - 1 : -1;
    gap.after = f < frames ? static_cast<long>(f) : -1;
    if (gap.last >= first && gap.first <= last) gaps.push_back(gap);
  }
  return gaps;
}

double TimeOf(const EditedTake& take, size_t f) { return static_cast<double>(take.markers.frame_numbers[f]); }

// Natural cubic spline through (t, y) (t increasing, at least 2 knots), evaluated at `at`.
class NaturalSpline {
 public:
  NaturalSpline(std::vector<double> t, std::vector<Eigen::Vector3d> y) : t_(std::move(t)), y_(std::move(y)) {
    const size_t n = t_.size();
    m_.assign(n, Eigen::Vector3d::Zero());
    if (n < 3) return;
    // Tridiagonal system for the second derivatives (Thomas algorithm), natural ends: m0 = mn = 0.
    std::vector<double> c(n, 0.0);
    std::vector<Eigen::Vector3d> d(n, Eigen::Vector3d::Zero());
    for (size_t i = 1; i + 1 < n; ++i) {
      const double h0 = t_[i] - t_[i - 1], h1 = t_[i + 1] - t_[i];
      const double a = h0 / 6.0, b = (h0 + h1) / 3.0, cc = h1 / 6.0;
      const Eigen::Vector3d rhs = (y_[i + 1] - y_[i]) / h1 - (y_[i] - y_[i - 1]) / h0;
      const double denom = b - a * c[i - 1];
      c[i] = cc / denom;
      d[i] = (rhs - a * d[i - 1]) / denom;
    }
    for (size_t i = n - 2; i >= 1; --i) {
      m_[i] = d[i] - c[i] * m_[i + 1];
      if (i == 1) break;
    }
  }

  Eigen::Vector3d At(double x) const {
    size_t i = 0;
    while (i + 2 < t_.size() && x > t_[i + 1]) ++i;
    const double h = t_[i + 1] - t_[i], a = (t_[i + 1] - x) / h, b = (x - t_[i]) / h;
    return a * y_[i] + b * y_[i + 1] + ((a * a * a - a) * m_[i] + (b * b * b - b) * m_[i + 1]) * h * h / 6.0;
  }

 private:
  std::vector<double> t_;
  std::vector<Eigen::Vector3d> y_;
  std::vector<Eigen::Vector3d> m_;
};

// At most `count` measured samples of `marker` from `from` walking by `step` (+1/-1), each at
// least `stride` frames from the one before.
void CollectKnots(const EditedTake& take, size_t marker, long from, int step, int count, long stride,
                  std::vector<double>* t, std::vector<Eigen::Vector3d>* y) {
  const long frames = static_cast<long>(take.markers.NumFrames());
  long last = -1;
  for (long f = from; f >= 0 && f < frames && count > 0; f += step) {
    if (!take.markers.Has(static_cast<size_t>(f), marker) || (last >= 0 && std::abs(f - last) < stride)) continue;
    t->push_back(TimeOf(take, static_cast<size_t>(f)));
    y->push_back(take.markers.At(static_cast<size_t>(f), marker));
    last = f;
    --count;
  }
}

size_t FillInterpolated(EditedTake* take, size_t marker, const Gap& gap, const FillOptions& options) {
  if (gap.before < 0 || gap.after < 0) return 0;
  std::vector<double> t;
  std::vector<Eigen::Vector3d> y;
  if (options.method == FillMethod::kLinear) {
    CollectKnots(*take, marker, gap.before, -1, 1, 1, &t, &y);
    CollectKnots(*take, marker, gap.after, +1, 1, 1, &t, &y);
  } else {
    // Knots spaced by a fifth of the gap: the spline follows the motion at the gap's own time
    // scale, and a long gap's shape does not hang on the noise of the last few samples.
    const long stride = std::max<long>(1, static_cast<long>(gap.last - gap.first + 1) / 5);
    std::vector<double> tb;
    std::vector<Eigen::Vector3d> yb;
    CollectKnots(*take, marker, gap.before, -1, options.context, stride, &tb, &yb);
    t.assign(tb.rbegin(), tb.rend());
    y.assign(yb.rbegin(), yb.rend());
    CollectKnots(*take, marker, gap.after, +1, options.context, stride, &t, &y);
  }
  const NaturalSpline spline(std::move(t), std::move(y));
  const uint8_t mark = static_cast<uint8_t>(options.method);
  for (size_t f = gap.first; f <= gap.last; ++f) take->Set(f, marker, spline.At(TimeOf(*take, f)), mark);
  return gap.last - gap.first + 1;
}

bool DonorsAt(const EditedTake& take, const std::vector<size_t>& donors, size_t f, Eigen::Matrix3Xd* out) {
  out->resize(3, static_cast<long>(donors.size()));
  for (size_t i = 0; i < donors.size(); ++i) {
    if (!take.markers.Has(f, donors[i])) return false;
    out->col(static_cast<long>(i)) = take.markers.At(f, donors[i]);
  }
  return true;
}

// Orthonormal frame from three points (relational): origin p0, x towards p1, z normal to the plane.
std::optional<Eigen::Matrix3d> AxesOf(const Eigen::Matrix3Xd& d) {
  const Eigen::Vector3d x = d.col(1) - d.col(0), in_plane = d.col(2) - d.col(0);
  const Eigen::Vector3d z = x.cross(in_plane);
  if (x.norm() < 1e-9 || z.norm() < 1e-9) return std::nullopt;
  Eigen::Matrix3d axes;
  axes.col(0) = x.normalized();
  axes.col(2) = z.normalized();
  axes.col(1) = axes.col(2).cross(axes.col(0));
  return axes;
}

std::optional<Eigen::Vector3d> Estimate(const FillOptions& options, const Eigen::Vector3d& target_ref,
                                        const Eigen::Matrix3Xd& donors_ref, const Eigen::Matrix3Xd& donors_now) {
  switch (options.method) {
    case FillMethod::kPattern:
      return Eigen::Vector3d(donors_now.col(0) + (target_ref - donors_ref.col(0)));
    case FillMethod::kRigid: {
      // The project's one rigid fit (geometry/rigid_fit.h): collinear donors place nothing.
      std::vector<Eigen::Vector3d> ref(donors_ref.cols()), now(donors_now.cols());
      for (long i = 0; i < donors_ref.cols(); ++i) ref[static_cast<size_t>(i)] = donors_ref.col(i);
      for (long i = 0; i < donors_now.cols(); ++i) now[static_cast<size_t>(i)] = donors_now.col(i);
      try {
        return FitRigid(ref, now).Apply(target_ref);
      } catch (const std::invalid_argument&) {
        return std::nullopt;
      }
    }
    case FillMethod::kRelational: {
      const std::optional<Eigen::Matrix3d> ref = AxesOf(donors_ref), now = AxesOf(donors_now);
      if (!ref || !now) return std::nullopt;
      const Eigen::Vector3d local = ref->transpose() * (target_ref - donors_ref.col(0));
      return Eigen::Vector3d(donors_now.col(0) + *now * local);
    }
    default:
      return std::nullopt;
  }
}

size_t FillFromDonors(EditedTake* take, size_t marker, const Gap& gap, const FillOptions& options) {
  Eigen::Matrix3Xd before_donors, after_donors, now;
  const bool has_before = gap.before >= 0 && DonorsAt(*take, options.donors, static_cast<size_t>(gap.before), &before_donors);
  const bool has_after = gap.after >= 0 && DonorsAt(*take, options.donors, static_cast<size_t>(gap.after), &after_donors);
  if (!has_before && !has_after) return 0;
  const Eigen::Vector3d before_target = has_before ? take->markers.At(static_cast<size_t>(gap.before), marker) : Eigen::Vector3d();
  const Eigen::Vector3d after_target = has_after ? take->markers.At(static_cast<size_t>(gap.after), marker) : Eigen::Vector3d();
  const uint8_t mark = static_cast<uint8_t>(options.method);
  size_t filled = 0;
  for (size_t f = gap.first; f <= gap.last; ++f) {
    if (!DonorsAt(*take, options.donors, f, &now)) continue;
    std::optional<Eigen::Vector3d> from_before, from_after;
    if (has_before) from_before = Estimate(options, before_target, before_donors, now);
    if (has_after) from_after = Estimate(options, after_target, after_donors, now);
    Eigen::Vector3d point;
    if (from_before && from_after) {
      const double t0 = TimeOf(*take, static_cast<size_t>(gap.before)), t1 = TimeOf(*take, static_cast<size_t>(gap.after));
      const double w = (TimeOf(*take, f) - t0) / (t1 - t0);
      point = (1.0 - w) * *from_before + w * *from_after;
    } else if (from_before) {
      point = *from_before;
    } else if (from_after) {
      point = *from_after;
    } else {
      continue;
    }
    take->Set(f, marker, point, mark);
    ++filled;
  }
  return filled;
}

}  // namespace

void FillOptions::Check() const {
  const auto refuse = [](const std::string& what) { throw std::invalid_argument(what); };
  if (context < 2 || context > 1000) refuse("context: " + std::to_string(context) + " must be 2-1000 samples");
  if (max_gap < 0) refuse("max_gap: " + std::to_string(max_gap) + " must be 0 (any) or a number of frames");
  const size_t n = donors.size();
  switch (method) {
    case FillMethod::kSpline:
    case FillMethod::kLinear:
      if (n != 0) refuse("donors: the " + std::string(FillMethodName(method)) + " fill takes no donors");
      break;
    case FillMethod::kPattern:
      if (n != 1) refuse("donors: a pattern fill takes one donor, not " + std::to_string(n));
      break;
    case FillMethod::kRigid:
      if (n < 3) refuse("donors: a rigid fill takes three or more donors, not " + std::to_string(n));
      break;
    case FillMethod::kRelational:
      if (n != 3) refuse("donors: a relational fill takes three donors (origin, axis, plane), not " + std::to_string(n));
      break;
  }
}

FillResult FillGaps(EditedTake* take, size_t marker, size_t first, size_t last, const FillOptions& options) {
  options.Check();
  for (size_t donor : options.donors)
    if (donor == marker) throw std::invalid_argument("donors: " + take->markers.names[marker] + " cannot be its own donor");
  FillResult result;
  for (const Gap& gap : GapsOf(*take, marker, first, last)) {
    const size_t length = gap.last - gap.first + 1;
    ++result.gaps_seen;
    size_t filled = 0;
    if (options.max_gap == 0 || length <= static_cast<size_t>(options.max_gap)) {
      filled = options.method == FillMethod::kSpline || options.method == FillMethod::kLinear
                   ? FillInterpolated(take, marker, gap, options)
                   : FillFromDonors(take, marker, gap, options);
    }
    result.samples_filled += filled;
    result.samples_left += length - filled;
    if (filled == length) ++result.gaps_filled;
  }
  return result;
}

}  // namespace mocap::edit
