// Metric computation for `eval`. Frames align by time (frame number / rate), so files written at
// different rates or with different Frame# numbering still compare the right instants.
#include "eval/marker_accuracy.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "eval/truth_exchanges.h"
#include "util/assignment.h"

namespace mocap {
namespace {

// Index of the truth frame at the result frame's instant, or -1. An instant matches when it is
// within a quarter of a truth frame period, tolerant of rounded Time columns.
long AlignedTruthFrame(const std::unordered_map<uint64_t, size_t>& truth_index, double truth_rate, double time) {
  const double position = time * truth_rate;
  const double nearest = std::round(position);
  if (nearest < 0.0 || std::abs(position - nearest) > 0.25) return -1;
  const auto it = truth_index.find(static_cast<uint64_t>(nearest));
  return it == truth_index.end() ? -1 : static_cast<long>(it->second);
}

}  // namespace

void MarkerEvalOptions::Check() const {
  if (!(gate_mm > 0.0 && gate_mm < 1e6)) throw std::invalid_argument("gate must be positive");
  if (min_cameras < 0) throw std::invalid_argument("min cameras must be >= 0");
}

MarkerEvalReport EvaluateMarkers(const MarkerTrajectories& truth, const MarkerTrajectories& result,
                                 const MarkerVisibility* visibility, const MarkerEvalOptions& options) {
  options.Check();
  if (!(truth.rate_hz > 0.0) || !(result.rate_hz > 0.0)) throw std::invalid_argument("truth and result need a rate");
  const size_t truth_markers = truth.NumMarkers();
  const size_t result_markers = result.NumMarkers();

  std::unordered_map<uint64_t, size_t> visibility_index;
  if (visibility != nullptr) {
    if (visibility->names != truth.names) {
      throw std::invalid_argument("visibility marker names differ from the truth's");
    }
    for (size_t f = 0; f < visibility->NumFrames(); ++f) visibility_index[visibility->frame_numbers[f]] = f;
  }

  // Labelling: the truth marker of each result column's name (-1: not a truth name).
  std::unordered_map<std::string, long> truth_marker_of_name;
  for (size_t m = 0; m < truth_markers; ++m) truth_marker_of_name[truth.names[m]] = static_cast<long>(m);
  std::vector<long> named_as(result_markers, -1);
  for (size_t k = 0; k < result_markers; ++k) {
    const auto it = truth_marker_of_name.find(result.names[k]);
    if (it != truth_marker_of_name.end()) named_as[k] = it->second;
  }
  const bool labels = std::any_of(named_as.begin(), named_as.end(), [](long m) { return m >= 0; });
  double worst_share = 1.0;

  std::unordered_map<uint64_t, size_t> truth_index;
  for (size_t f = 0; f < truth.NumFrames(); ++f) truth_index[truth.frame_numbers[f]] = f;
  // For each truth frame, the aligned result frame (or none: the result wrote no row then).
  std::vector<long> result_of_truth(truth.NumFrames(), -1);
  MarkerEvalReport report;
  report.gate_mm = options.gate_mm;
  report.visibility_used = visibility != nullptr;
  for (size_t r = 0; r < result.NumFrames(); ++r) {
    const long t = AlignedTruthFrame(truth_index, truth.rate_hz, result.TimeOf(r));
    if (t < 0 || result_of_truth[t] >= 0) {
      ++report.unaligned_result_frames;
    } else {
      result_of_truth[t] = static_cast<long>(r);
      ++report.result_frames;
    }
  }

  std::vector<char> truth_ever(truth_markers, 0), result_ever(result_markers, 0);
  std::vector<long> last_match(result_markers, -1);
  const TruthExchanges exchanges = FindTruthExchanges(truth);
  report.truth_exchanges = exchanges.count;
  std::vector<double> errors;
  std::vector<size_t> present_truth, present_result;
  report.frames = truth.NumFrames();
  for (size_t t = 0; t < truth.NumFrames(); ++t) {
    present_truth.clear();
    present_result.clear();
    for (size_t m = 0; m < truth_markers; ++m) {
      if (truth.Has(t, m)) present_truth.push_back(m);
    }
    const long r = result_of_truth[t];
    if (r >= 0) {
      for (size_t k = 0; k < result_markers; ++k) {
        if (result.Has(r, k)) present_result.push_back(k);
      }
    }
    Eigen::MatrixXd cost(present_result.size(), present_truth.size());
    for (size_t i = 0; i < present_result.size(); ++i) {
      for (size_t j = 0; j < present_truth.size(); ++j) {
        cost(i, j) = (result.At(r, present_result[i]) - truth.At(t, present_truth[j])).norm();
      }
    }
    const std::vector<int> match = SolveAssignment(cost, options.gate_mm);

    std::vector<char> truth_matched(present_truth.size(), 0);
    size_t frame_correct = 0;
    for (size_t i = 0; i < present_result.size(); ++i) {
      const size_t column = present_result[i];
      result_ever[column] = 1;
      ++report.result_points;
      if (named_as[column] >= 0) {
        ++report.named_points;
        if (match[i] >= 0 && static_cast<long>(present_truth[match[i]]) == named_as[column]) {
          ++report.correctly_named;
          ++frame_correct;
        } else {
          ++report.wrongly_named;
        }
      }
      if (match[i] < 0) {
        ++report.ghosts;
        continue;
      }
      truth_matched[match[i]] = 1;
      errors.push_back(cost(i, match[i]));
      const long marker = static_cast<long>(present_truth[match[i]]);
      // A swap: this output trajectory now follows a different truth marker than it last did.
      if (last_match[column] >= 0 && last_match[column] != marker) {
        ++report.swaps;
        if (exchanges.Involves(t, marker) || exchanges.Involves(t, static_cast<size_t>(last_match[column]))) {
          ++report.swaps_at_truth_exchanges;
        }
      }
      last_match[column] = marker;
    }

    if (labels && !present_result.empty())
      worst_share = std::min(worst_share, static_cast<double>(frame_correct) / present_result.size());

    long visibility_frame = -1;
    if (visibility != nullptr) {
      const auto it = visibility_index.find(truth.frame_numbers[t]);
      if (it != visibility_index.end()) visibility_frame = static_cast<long>(it->second);
    }
    for (size_t j = 0; j < present_truth.size(); ++j) {
      const size_t marker = present_truth[j];
      truth_ever[marker] = 1;
      ++report.truth_points;
      // Without a visibility row for this frame every present marker counts.
      const bool expected = visibility == nullptr || visibility_frame < 0 ||
                            visibility->At(visibility_frame, marker) >= options.min_cameras;
      if (!expected) continue;
      ++report.expected_points;
      if (!truth_matched[j]) ++report.missing;
    }
  }

  report.matched = errors.size();
  report.labels_compared = labels;
  if (labels && report.result_points > 0) {
    report.correct_share = static_cast<double>(report.correctly_named) / report.result_points;
    report.wrong_share = static_cast<double>(report.wrongly_named) / report.result_points;
    report.worst_frame_correct_share = worst_share;
  }
  report.truth_markers = static_cast<size_t>(std::count(truth_ever.begin(), truth_ever.end(), 1));
  report.trajectories = static_cast<size_t>(std::count(result_ever.begin(), result_ever.end(), 1));
  if (!errors.empty()) {
    double sum = 0.0, sum_squares = 0.0;
    for (double e : errors) {
      sum += e;
      sum_squares += e * e;
    }
    report.mean_error_mm = sum / errors.size();
    report.rmse_mm = std::sqrt(sum_squares / errors.size());
    report.max_error_mm = *std::max_element(errors.begin(), errors.end());
    // Nearest-rank 95th percentile.
    const size_t rank = static_cast<size_t>(std::ceil(0.95 * errors.size())) - 1;
    std::nth_element(errors.begin(), errors.begin() + rank, errors.end());
    report.p95_error_mm = errors[rank];
  }
  if (report.frames > 0) {
    report.ghosts_per_frame = static_cast<double>(report.ghosts) / report.frames;
    report.missing_per_frame = static_cast<double>(report.missing) / report.frames;
  }
  if (report.truth_markers > 0) {
    report.fragmentation = static_cast<double>(report.trajectories) / report.truth_markers;
  }
  return report;
}

nlohmann::json MarkerEvalReport::ToJson() const {
  return {{"frames", frames},
          {"result_frames", result_frames},
          {"unaligned_result_frames", unaligned_result_frames},
          {"truth_markers", truth_markers},
          {"truth_points", truth_points},
          {"expected_points", expected_points},
          {"result_points", result_points},
          {"matched", matched},
          {"rmse_mm", rmse_mm},
          {"mean_error_mm", mean_error_mm},
          {"p95_error_mm", p95_error_mm},
          {"max_error_mm", max_error_mm},
          {"ghosts", ghosts},
          {"ghosts_per_frame", ghosts_per_frame},
          {"missing", missing},
          {"missing_per_frame", missing_per_frame},
          {"trajectories", trajectories},
          {"fragmentation", fragmentation},
          {"swaps", swaps},
          {"truth_exchanges", truth_exchanges},
          {"swaps_at_truth_exchanges", swaps_at_truth_exchanges},
          {"visibility_used", visibility_used},
          {"gate_mm", gate_mm},
          {"labels_compared", labels_compared},
          {"named_points", named_points},
          {"correctly_named", correctly_named},
          {"wrongly_named", wrongly_named},
          {"correct_share", correct_share},
          {"wrong_share", wrong_share},
          {"worst_frame_correct_share", worst_frame_correct_share}};
}

std::string MarkerEvalReport::ToText() const {
  std::ostringstream out;
  out << fmt::format("frames            {} truth, {} aligned result rows, {} result rows at other times\n", frames,
                     result_frames, unaligned_result_frames);
  out << fmt::format("matched           {} of {} truth points ({} output points, gate {} mm)\n", matched,
                     truth_points, result_points, gate_mm);
  out << fmt::format("rmse_mm           {:.4f}   (mean {:.4f}, p95 {:.4f}, max {:.4f})\n", rmse_mm, mean_error_mm,
                     p95_error_mm, max_error_mm);
  out << fmt::format("ghosts_per_frame  {:.4f}   ({} ghosts)\n", ghosts_per_frame, ghosts);
  out << fmt::format("missing_per_frame {:.4f}   ({} of {} expected points{})\n", missing_per_frame, missing,
                     expected_points, visibility_used ? ", seen by >= 2 cameras" : ", all present truth counted");
  out << fmt::format("trajectories      {}   for {} truth markers (fragmentation {:.3f})\n", trajectories,
                     truth_markers, fragmentation);
  out << fmt::format("swaps             {}", swaps);
  if (truth_exchanges > 0) {
    out << fmt::format("   ({} where the truth's own markers exchange places: {} such exchanges)", swaps_at_truth_exchanges,
                       truth_exchanges);
  }
  out << "\n";
  if (labels_compared) {
    out << fmt::format("labels            {:.3f}% of output points correctly named, {:.3f}% wrongly ({} named of {}; "
                       "worst frame {:.1f}% correct)\n",
                       100.0 * correct_share, 100.0 * wrong_share, named_points, result_points,
                       100.0 * worst_frame_correct_share);
  }
  return out.str();
}

}  // namespace mocap
