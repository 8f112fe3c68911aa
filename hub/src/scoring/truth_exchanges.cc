// Exchanges judged pair by pair at every boundary of consecutive truth frames.
#include "scoring/truth_exchanges.h"

#include <algorithm>

#include "util/join_roughness.h"

namespace mocap {

bool TruthExchanges::Involves(size_t frame_index, size_t marker) const {
  if (frame_index >= markers_at_frame.size()) return false;
  const std::vector<size_t>& markers = markers_at_frame[frame_index];
  return std::binary_search(markers.begin(), markers.end(), marker);
}

TruthExchanges FindTruthExchanges(const MarkerTrajectories& truth, const TruthExchangeOptions& options) {
  TruthExchanges exchanges;
  const size_t frames = truth.NumFrames();
  exchanges.markers_at_frame.resize(frames);
  const double radius2 = options.radius_mm * options.radius_mm;
  const double min_jump2 = options.min_jump_mm * options.min_jump_mm;
  std::vector<size_t> present;
  for (size_t t = 2; t + 1 < frames; ++t) {
    // Rows t-2 ... t+1 must be consecutive frames.
    if (truth.frame_numbers[t + 1] - truth.frame_numbers[t - 2] != 3) continue;
    present.clear();
    for (size_t m = 0; m < truth.NumMarkers(); ++m) {
      if (truth.Has(t - 2, m) && truth.Has(t - 1, m) && truth.Has(t, m) && truth.Has(t + 1, m)) present.push_back(m);
    }
    std::vector<size_t>& involved = exchanges.markers_at_frame[t];
    for (size_t i = 0; i < present.size(); ++i) {
      const size_t a = present[i];
      for (size_t j = i + 1; j < present.size(); ++j) {
        const size_t b = present[j];
        if ((truth.At(t - 1, a) - truth.At(t - 1, b)).squaredNorm() > radius2) continue;
        const auto join = [&](size_t past, size_t next) {
          return JoinRoughness(truth.At(t - 2, past), truth.At(t - 1, past), truth.At(t, next), truth.At(t + 1, next));
        };
        const double labelled = join(a, a) + join(b, b);
        const double traded = join(a, b) + join(b, a);
        if (traded > options.ratio * labelled || labelled - traded < min_jump2) continue;
        ++exchanges.count;
        involved.push_back(a);
        involved.push_back(b);
      }
    }
    std::sort(involved.begin(), involved.end());
    involved.erase(std::unique(involved.begin(), involved.end()), involved.end());
  }
  return exchanges;
}

}  // namespace mocap
