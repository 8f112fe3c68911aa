// PCA compression of marker trajectories (see trajectory_pca.h).
#include "archive/trajectory_pca.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <Eigen/SVD>

namespace mocap {
namespace {

using Eigen::MatrixXd;

// The window's coordinates of one group, gaps filled by linear interpolation along time (held at
// the ends), and which samples were really there.
struct WindowData {
  MatrixXd values;                 // frames x (3 * group size)
  std::vector<bool> present;       // frames x group size, row-major
  size_t present_count = 0;
};

WindowData GatherWindow(const MarkerTrajectories& trajectories, const std::vector<int>& group, size_t first,
                        size_t frames) {
  WindowData data;
  const size_t m = group.size();
  data.values = MatrixXd::Zero(static_cast<Eigen::Index>(frames), static_cast<Eigen::Index>(3 * m));
  data.present.assign(frames * m, false);
  for (size_t j = 0; j < m; ++j) {
    const size_t marker = static_cast<size_t>(group[j]);
    long last = -1;  // last present frame in the window
    for (size_t t = 0; t < frames; ++t) {
      if (!trajectories.Has(first + t, marker)) continue;
      const Eigen::Vector3d& p = trajectories.At(first + t, marker);
      data.present[t * m + j] = true;
      ++data.present_count;
      for (int a = 0; a < 3; ++a) data.values(static_cast<Eigen::Index>(t), static_cast<Eigen::Index>(3 * j + a)) = p[a];
      const size_t from = last < 0 ? 0 : static_cast<size_t>(last) + 1;
      for (size_t g = from; g < t; ++g) {
        const double s = last < 0 ? 1.0 : static_cast<double>(g - static_cast<size_t>(last)) / static_cast<double>(t - static_cast<size_t>(last));
        for (int a = 0; a < 3; ++a) {
          const double before = last < 0 ? p[a] : data.values(last, static_cast<Eigen::Index>(3 * j + a));
          data.values(static_cast<Eigen::Index>(g), static_cast<Eigen::Index>(3 * j + a)) = before + s * (p[a] - before);
        }
      }
      last = static_cast<long>(t);
    }
    if (last >= 0) {
      for (size_t g = static_cast<size_t>(last) + 1; g < frames; ++g)
        for (int a = 0; a < 3; ++a)
          data.values(static_cast<Eigen::Index>(g), static_cast<Eigen::Index>(3 * j + a)) = data.values(last, static_cast<Eigen::Index>(3 * j + a));
    }
  }
  return data;
}

int32_t Quantise(double value, double step) {
  return static_cast<int32_t>(std::clamp(std::round(value / step), -double{kMaxArchiveInteger}, double{kMaxArchiveInteger}));
}

// K components quantised so that they add about `quantisation_mm` RMS 3D error per point, half
// from each factor. With orthonormal weights, a step d on every time value adds K d^2 / 12 per
// frame over the group's m markers; a step e_k on component k's weights adds
// sigma_k^2 3 e_k^2 / (12 T) per marker. Equal shares per component give the steps below.
PcaBlock MakeBlock(const Eigen::BDCSVD<MatrixXd>& svd, const Eigen::RowVectorXd& mean, int components,
                   double quantisation_mm) {
  const MatrixXd& u = svd.matrixU();
  const MatrixXd& v = svd.matrixV();
  const size_t frames = static_cast<size_t>(u.rows());
  const size_t channels = static_cast<size_t>(v.rows());
  const size_t k_count = static_cast<size_t>(components);
  const double markers = static_cast<double>(channels) / 3.0;
  PcaBlock block;
  block.components = components;
  block.mean.resize(channels);
  for (size_t c = 0; c < channels; ++c) block.mean[c] = Quantise(mean[static_cast<Eigen::Index>(c)], kArchiveMeanStepMm);
  if (k_count == 0) return block;
  const double share = 0.5 * quantisation_mm * quantisation_mm;
  block.time_step = static_cast<float>(std::sqrt(12.0 * markers * share / static_cast<double>(k_count)));
  block.time.resize(frames * k_count);
  block.weights.resize(channels * k_count);
  for (size_t k = 0; k < k_count; ++k) {
    const Eigen::Index kk = static_cast<Eigen::Index>(k);
    const double sigma = std::max(svd.singularValues()[kk], 1e-9);
    for (size_t t = 0; t < frames; ++t)
      block.time[t * k_count + k] = Quantise(u(static_cast<Eigen::Index>(t), kk) * sigma, block.time_step);
    // At least 2^-24: a weight is at most 1, so its integer stays within kMaxArchiveInteger.
    const double step = std::max(std::sqrt(4.0 * static_cast<double>(frames) * share / static_cast<double>(k_count)) / sigma,
                                 1.0 / (1 << 24));
    block.weight_steps.push_back(static_cast<float>(step));
    for (size_t c = 0; c < channels; ++c)
      block.weights[c * k_count + k] = Quantise(v(static_cast<Eigen::Index>(c), kk), static_cast<double>(block.weight_steps.back()));
  }
  return block;
}

// The block's values as decoded: frames x channels.
MatrixXd ExpandBlock(const PcaBlock& block, size_t frames) {
  const size_t channels = block.mean.size();
  const size_t k_count = static_cast<size_t>(block.components);
  MatrixXd time(static_cast<Eigen::Index>(frames), static_cast<Eigen::Index>(k_count));
  MatrixXd weights(static_cast<Eigen::Index>(k_count), static_cast<Eigen::Index>(channels));
  for (size_t k = 0; k < k_count; ++k) {
    for (size_t t = 0; t < frames; ++t)
      time(static_cast<Eigen::Index>(t), static_cast<Eigen::Index>(k)) =
          static_cast<double>(block.time_step) * block.time[t * k_count + k];
    for (size_t c = 0; c < channels; ++c)
      weights(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(c)) =
          static_cast<double>(block.weight_steps[k]) * block.weights[c * k_count + k];
  }
  MatrixXd values = time * weights;
  for (size_t c = 0; c < channels; ++c) values.col(static_cast<Eigen::Index>(c)).array() += kArchiveMeanStepMm * block.mean[c];
  return values;
}

// Sum of squared 3D errors over the present samples.
double SquaredError(const WindowData& data, const MatrixXd& decoded) {
  const size_t m = static_cast<size_t>(data.values.cols()) / 3;
  const MatrixXd diff = decoded - data.values;
  double sum = 0.0;
  for (Eigen::Index t = 0; t < diff.rows(); ++t)
    for (size_t j = 0; j < m; ++j)
      if (data.present[static_cast<size_t>(t) * m + j])
        sum += diff.block(t, static_cast<Eigen::Index>(3 * j), 1, 3).squaredNorm();
  return sum;
}

PcaBlock CompressWindow(const WindowData& data, const TrajectoryPcaOptions& options) {
  const Eigen::Index frames = data.values.rows();
  const size_t m = static_cast<size_t>(data.values.cols()) / 3;
  // Means over the present samples only, so that interpolated fill does not move them.
  Eigen::RowVectorXd mean = Eigen::RowVectorXd::Zero(data.values.cols());
  for (size_t j = 0; j < m; ++j) {
    size_t count = 0;
    for (Eigen::Index t = 0; t < frames; ++t) {
      if (!data.present[static_cast<size_t>(t) * m + j]) continue;
      mean.segment(static_cast<Eigen::Index>(3 * j), 3) += data.values.block(t, static_cast<Eigen::Index>(3 * j), 1, 3);
      ++count;
    }
    if (count > 0) mean.segment(static_cast<Eigen::Index>(3 * j), 3) /= static_cast<double>(count);
  }
  const MatrixXd centred = data.values.rowwise() - mean;
  const Eigen::BDCSVD<MatrixXd> svd(centred, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const int rank = static_cast<int>(std::min<Eigen::Index>(svd.singularValues().size(),
                                                            static_cast<Eigen::Index>(kMaxArchiveComponents)));
  if (options.components > 0 || data.present_count == 0)
    return MakeBlock(svd, mean, data.present_count == 0 ? 0 : std::min(options.components, rank),
                     options.quantisation_mm);
  // The smallest K within the bound, measured after quantisation; the error falls with K (a binary
  // search over it), and K = rank reproduces the window up to quantisation. The quantisation takes
  // what the truncation leaves of the budget (the truncation's share estimated from the singular
  // values over every sample, filled ones too), at least a tenth of it.
  const double bound = options.max_error_mm * options.max_error_mm * static_cast<double>(data.present_count);
  const double points = static_cast<double>(frames) * static_cast<double>(m);
  const Eigen::VectorXd& sigma = svd.singularValues();
  const auto quantisation_for = [&](int k) {
    const double truncation = sigma.tail(sigma.size() - k).squaredNorm() / points;
    const double budget = options.max_error_mm * options.max_error_mm;
    return std::sqrt(std::max(0.8 * (budget - truncation), 0.1 * budget));
  };
  int lo = 0, hi = rank;
  PcaBlock best = MakeBlock(svd, mean, hi, quantisation_for(hi));
  while (lo < hi) {
    const int mid = (lo + hi) / 2;
    PcaBlock candidate = MakeBlock(svd, mean, mid, quantisation_for(mid));
    if (SquaredError(data, ExpandBlock(candidate, static_cast<size_t>(frames))) <= bound) {
      hi = mid;
      best = std::move(candidate);
    } else {
      lo = mid + 1;
    }
  }
  return best;
}

void CheckGroups(const std::vector<std::vector<int>>& groups, size_t markers) {
  std::vector<int> seen(markers, 0);
  for (const std::vector<int>& group : groups) {
    if (group.empty()) throw std::invalid_argument("archive groups: a group holds no marker");
    for (int marker : group) {
      if (marker < 0 || static_cast<size_t>(marker) >= markers)
        throw std::invalid_argument("archive groups: marker index " + std::to_string(marker) + " is outside 0.." +
                                    std::to_string(markers - 1));
      ++seen[static_cast<size_t>(marker)];
    }
  }
  for (size_t i = 0; i < markers; ++i)
    if (seen[i] != 1)
      throw std::invalid_argument("archive groups: marker " + std::to_string(i) + " is in " + std::to_string(seen[i]) +
                                  " groups; each marker must be in exactly one");
}

}  // namespace

void TrajectoryPcaOptions::Check() const {
  if (window_frames < 1 || static_cast<uint32_t>(window_frames) > kMaxArchiveWindowFrames)
    throw std::invalid_argument("window_frames: " + std::to_string(window_frames) + " is outside 1.." +
                                std::to_string(kMaxArchiveWindowFrames));
  if (components < 0 || static_cast<uint32_t>(components) > kMaxArchiveComponents)
    throw std::invalid_argument("components: " + std::to_string(components) + " is outside 0.." +
                                std::to_string(kMaxArchiveComponents) + " (0: chosen by max_error_mm)");
  if (components == 0 && !(max_error_mm > 0.0 && std::isfinite(max_error_mm)))
    throw std::invalid_argument("max_error_mm: " + std::to_string(max_error_mm) + " must be a finite number > 0");
  if (!(quantisation_mm >= 1e-4 && quantisation_mm <= 1e3))
    throw std::invalid_argument("quantisation_mm: " + std::to_string(quantisation_mm) + " is outside 0.0001..1000");
}

CompressedTrajectories CompressTrajectories(const MarkerTrajectories& trajectories,
                                            const std::vector<std::vector<int>>& groups,
                                            const TrajectoryPcaOptions& options) {
  options.Check();
  const size_t frames = trajectories.NumFrames();
  const size_t markers = trajectories.NumMarkers();
  if (frames == 0 || markers == 0) throw std::invalid_argument("archive: the trajectories hold no frames or no markers");
  if (markers > kMaxArchiveMarkers)
    throw std::invalid_argument("archive: " + std::to_string(markers) + " markers, more than the format's " +
                                std::to_string(kMaxArchiveMarkers));
  if (static_cast<uint64_t>(frames) * markers > kMaxArchivePoints)
    throw std::invalid_argument("archive: " + std::to_string(frames) + " frames x " + std::to_string(markers) +
                                " markers is more than the format's " + std::to_string(kMaxArchivePoints) + " points");
  if (!(trajectories.rate_hz > 0.0 && std::isfinite(trajectories.rate_hz)))
    throw std::invalid_argument("archive: rate " + std::to_string(trajectories.rate_hz) + " Hz is not a positive number");
  for (size_t i = 1; i < frames; ++i)
    if (trajectories.frame_numbers[i] <= trajectories.frame_numbers[i - 1])
      throw std::invalid_argument("archive: frame numbers must increase (frame " + std::to_string(i) + ")");

  CompressedTrajectories out;
  out.rate_hz = trajectories.rate_hz;
  out.names = trajectories.names;
  out.frame_numbers = trajectories.frame_numbers;
  out.window_frames = options.window_frames;
  if (groups.empty()) {
    out.groups.emplace_back();
    for (size_t i = 0; i < markers; ++i) out.groups.back().push_back(static_cast<int>(i));
  } else {
    CheckGroups(groups, markers);
    out.groups = groups;
  }
  out.gap_runs.resize(markers);
  for (size_t marker = 0; marker < markers; ++marker) {
    std::vector<uint32_t>& runs = out.gap_runs[marker];
    bool present = true;
    uint32_t run = 0;
    for (size_t t = 0; t < frames; ++t) {
      if (trajectories.Has(t, marker) != present) {
        runs.push_back(run);
        present = !present;
        run = 0;
      }
      ++run;
    }
    runs.push_back(run);
  }
  for (size_t w = 0; w < out.NumWindows(); ++w) {
    const size_t first = w * static_cast<size_t>(options.window_frames);
    const size_t count = std::min(static_cast<size_t>(options.window_frames), frames - first);
    for (const std::vector<int>& group : out.groups)
      out.blocks.push_back(CompressWindow(GatherWindow(trajectories, group, first, count), options));
  }
  return out;
}

MarkerTrajectories DecompressTrajectories(const CompressedTrajectories& compressed) {
  MarkerTrajectories out;
  out.rate_hz = compressed.rate_hz;
  out.names = compressed.names;
  out.frame_numbers = compressed.frame_numbers;
  const size_t frames = compressed.NumFrames();
  const size_t markers = compressed.names.size();
  out.points.assign(frames * markers, MarkerTrajectories::Gap());
  const size_t window = static_cast<size_t>(compressed.window_frames);
  for (size_t w = 0; w < compressed.NumWindows(); ++w) {
    const size_t first = w * window;
    const size_t count = std::min(window, frames - first);
    for (size_t g = 0; g < compressed.groups.size(); ++g) {
      const std::vector<int>& group = compressed.groups[g];
      const MatrixXd values = ExpandBlock(compressed.blocks[w * compressed.groups.size() + g], count);
      for (size_t t = 0; t < count; ++t)
        for (size_t j = 0; j < group.size(); ++j)
          out.At(first + t, static_cast<size_t>(group[j])) =
              values.block(static_cast<Eigen::Index>(t), static_cast<Eigen::Index>(3 * j), 1, 3).transpose();
    }
  }
  for (size_t marker = 0; marker < markers; ++marker) {
    size_t t = 0;
    bool present = true;
    for (uint32_t run : compressed.gap_runs[marker]) {
      if (!present)
        for (size_t i = 0; i < run; ++i) out.At(t + i, marker) = MarkerTrajectories::Gap();
      t += run;
      present = !present;
    }
  }
  return out;
}

double TrajectoryRmsError(const MarkerTrajectories& reference, const MarkerTrajectories& other) {
  if (reference.points.size() != other.points.size())
    throw std::invalid_argument("TrajectoryRmsError: the two trajectories differ in shape");
  double sum = 0.0;
  size_t count = 0;
  for (size_t i = 0; i < reference.points.size(); ++i) {
    if (MarkerTrajectories::IsGap(reference.points[i]) || MarkerTrajectories::IsGap(other.points[i])) continue;
    sum += (reference.points[i] - other.points[i]).squaredNorm();
    ++count;
  }
  return count > 0 ? std::sqrt(sum / static_cast<double>(count)) : 0.0;
}

}  // namespace mocap
