// Rigid-body pose accuracy (see body_accuracy.h).
#include "eval/body_accuracy.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace mocap {
namespace {

constexpr double kGrossMm = 20.0;
constexpr double kGrossDeg = 10.0;

double Percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  const size_t rank = static_cast<size_t>(std::ceil(q * static_cast<double>(v.size()))) - (q > 0.0 ? 1 : 0);
  std::nth_element(v.begin(), v.begin() + static_cast<long>(std::min(rank, v.size() - 1)), v.end());
  return v[std::min(rank, v.size() - 1)];
}

}  // namespace

BodyEvalReport EvaluateBodies(const std::vector<BodyPoseRecord>& truth, const std::vector<BodyPoseRecord>& result,
                              const MarkerVisibility* visibility) {
  BodyEvalReport report;
  report.visibility_used = visibility != nullptr;
  std::map<std::pair<std::string, uint64_t>, const BodyPoseRecord*> found;
  for (const BodyPoseRecord& r : result) found[{r.body, r.frame}] = &r;
  std::unordered_map<std::string, size_t> index;
  std::vector<std::vector<double>> mm, deg;
  std::unordered_map<uint64_t, size_t> visibility_row;
  if (visibility)
    for (size_t f = 0; f < visibility->NumFrames(); ++f) visibility_row[visibility->frame_numbers[f]] = f;
  std::unordered_map<std::string, std::vector<size_t>> columns_of;  // body -> its visibility columns
  if (visibility)
    for (size_t c = 0; c < visibility->names.size(); ++c) {
      const std::string& name = visibility->names[c];
      const size_t colon = name.rfind(':');
      if (colon != std::string::npos) columns_of[name.substr(0, colon)].push_back(c);
    }
  for (const BodyPoseRecord& t : truth) {
    auto [it, added] = index.emplace(t.body, report.bodies.size());
    if (added) {
      report.bodies.push_back({});
      report.bodies.back().name = t.body;
      mm.emplace_back(), deg.emplace_back();
    }
    BodyEvalReport::Body& b = report.bodies[it->second];
    ++b.truth_frames;
    bool seen = true;
    if (visibility) {
      const auto row = t.frame > 0 ? visibility_row.find(t.frame - 1) : visibility_row.end();
      int markers = 0;
      if (row != visibility_row.end())
        for (size_t c : columns_of[t.body]) markers += visibility->At(row->second, c) >= 2;
      seen = markers >= 3;
    }
    b.seen += seen;
    const auto r = found.find({t.body, t.frame});
    if (r == found.end() || !r->second->tracked) continue;
    ++b.fitted;
    b.fitted_when_seen += seen;
    const double e_mm = (r->second->pivot - t.pivot).norm();
    const double e_deg = r->second->orientation.angularDistance(t.orientation) * 180.0 / 3.14159265358979323846;
    mm[it->second].push_back(e_mm);
    deg[it->second].push_back(e_deg);
    b.gross += e_mm > kGrossMm || e_deg > kGrossDeg;
  }
  for (size_t i = 0; i < report.bodies.size(); ++i) {
    BodyEvalReport::Body& b = report.bodies[i];
    bool any = false;
    for (const BodyPoseRecord& r : result) any = any || r.body == b.name;
    if (!any) throw std::invalid_argument("the result has no body '" + b.name + "'");
    b.available_share = b.seen ? static_cast<double>(b.fitted_when_seen) / b.seen : 0.0;
    b.p50_mm = Percentile(mm[i], 0.5), b.p95_mm = Percentile(mm[i], 0.95);
    b.p50_deg = Percentile(deg[i], 0.5), b.p95_deg = Percentile(deg[i], 0.95);
    b.max_mm = mm[i].empty() ? 0.0 : *std::max_element(mm[i].begin(), mm[i].end());
    b.max_deg = deg[i].empty() ? 0.0 : *std::max_element(deg[i].begin(), deg[i].end());
  }
  return report;
}

nlohmann::json BodyEvalReport::ToJson() const {
  nlohmann::json list = nlohmann::json::array();
  for (const Body& b : bodies)
    list.push_back({{"name", b.name}, {"truth_frames", b.truth_frames}, {"fitted", b.fitted}, {"seen", b.seen},
                    {"fitted_when_seen", b.fitted_when_seen}, {"available_share", b.available_share},
                    {"gross", b.gross}, {"p50_mm", b.p50_mm}, {"p95_mm", b.p95_mm}, {"max_mm", b.max_mm},
                    {"p50_deg", b.p50_deg}, {"p95_deg", b.p95_deg}, {"max_deg", b.max_deg}});
  return {{"bodies", list}, {"visibility_used", visibility_used}};
}

std::string BodyEvalReport::ToText() const {
  std::ostringstream out;
  for (const Body& b : bodies)
    out << fmt::format("body {:<12} fitted {}/{} frames ({:.2f}% of {} with >= 3 markers seen{}); error p50/p95/max "
                       "{:.3f}/{:.3f}/{:.3f} mm, {:.3f}/{:.3f}/{:.3f} deg; {} gross (> 20 mm or 10 deg)\n",
                       b.name, b.fitted, b.truth_frames, 100.0 * b.available_share, b.seen,
                       visibility_used ? "" : ": all frames", b.p50_mm, b.p95_mm, b.max_mm, b.p50_deg, b.p95_deg,
                       b.max_deg, b.gross);
  return out.str();
}

}  // namespace mocap
