// The wand calibration report's figures and page (see wand_report.h).
#include "calib/wand_report.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "io/calibration_json.h"
#include "util/json_file.h"

namespace mocap {

// The console's plotting module, embedded at build time (cmake/EmbedText.cmake).
extern const char kCalibrationPlotsJs[];

namespace {

nlohmann::json LengthJson(const LengthErrorStats& s) {
  return {{"frames", s.count},
          {"mean_mm", s.mean_mm},
          {"rms_mm", s.rms_mm},
          {"median_abs_mm", s.median_abs_mm},
          {"p95_abs_mm", s.p95_abs_mm},
          {"max_abs_mm", s.max_abs_mm}};
}

double Quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  const size_t k = std::min(values.size() - 1, static_cast<size_t>(q * static_cast<double>(values.size())));
  std::nth_element(values.begin(), values.begin() + static_cast<long>(k), values.end());
  return values[k];
}

// Counts of values in `bins` bins of width `bin` from `start`; values beyond either end go to
// the end bins, so that no sample is lost from the plot.
nlohmann::json Histogram(const std::vector<double>& values, double start, double bin, int bins) {
  std::vector<uint32_t> counts(static_cast<size_t>(bins), 0);
  for (double v : values) {
    if (!std::isfinite(v)) continue;
    const int i = std::clamp(static_cast<int>(std::floor((v - start) / bin)), 0, bins - 1);
    ++counts[static_cast<size_t>(i)];
  }
  return {{"start", start}, {"bin", bin}, {"counts", counts}};
}

nlohmann::json ResidualJson(const std::vector<float>& residuals) {
  std::vector<double> values(residuals.begin(), residuals.end());
  const double p99 = Quantile(values, 0.99);
  const int bins = 30;
  const double bin = std::max(p99 * 1.05 / bins, 1e-3);
  return {{"observations", values.size()},
          {"p50_px", Quantile(values, 0.5)},
          {"p95_px", Quantile(values, 0.95)},
          {"max_px", values.empty() ? 0.0 : *std::max_element(values.begin(), values.end())},
          {"histogram", Histogram(values, 0.0, bin, bins)}};
}

// A frame for the layout plots with z up: the mean of the cameras' image-up directions (cameras
// are mounted without much roll), x along the first camera's image rows, levelled.
Eigen::Matrix3d PlotFromWorld(const Rig& rig) {
  Eigen::Vector3d up = Eigen::Vector3d::Zero();
  for (const Camera& c : rig.cameras) up -= c.rotation.transpose() * Eigen::Vector3d::UnitY();
  if (rig.cameras.empty() || up.norm() < 1e-9) return Eigen::Matrix3d::Identity();
  up.normalize();
  Eigen::Vector3d x = rig.cameras.front().rotation.transpose() * Eigen::Vector3d::UnitX();
  x -= x.dot(up) * up;
  if (x.norm() < 1e-9) x = up.unitOrthogonal();
  x.normalize();
  Eigen::Matrix3d plot_from_world;
  plot_from_world.row(0) = x.transpose();
  plot_from_world.row(1) = up.cross(x).transpose();
  plot_from_world.row(2) = up.transpose();
  return plot_from_world;
}

nlohmann::json Vec(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace

nlohmann::json WandResultJson(const WandCalibrationResult& result, const WandGeometry& wand,
                              const RatingThresholds& thresholds) {
  nlohmann::json cameras = nlohmann::json::array();
  size_t accepted = 0;
  for (const CameraCalibrationReport& c : result.cameras) {
    const CameraRating rating = RateCamera(c, thresholds);
    accepted += c.accepted;
    cameras.push_back({{"id", c.id},
                       {"accepted", c.accepted},
                       {"reason", c.reason},
                       {"rating", CalibrationRatingName(rating.rating)},
                       {"rating_by_rms", CalibrationRatingName(rating.by_rms)},
                       {"rating_by_wand_length", CalibrationRatingName(rating.by_wand_length)},
                       {"rating_limited_by", rating.limited_by},
                       {"views_selected", c.views_selected},
                       {"views_used", c.views_used},
                       {"reprojection_rms_px", c.reprojection_rms_px},
                       {"coverage", c.coverage},
                       {"wand_length_error", LengthJson(c.wand_length)}});
  }
  const CameraRating rig = RateRig(result, thresholds);
  return {{"method", "wand"},
          {"wand_length_mm", wand.LengthMm()},
          {"wand_markers", wand.MarkerCount()},
          {"reference_camera", result.reference_camera_id},
          {"frames", result.frames_in},
          {"frames_selected", result.frames_selected},
          {"frames_used", result.frames_used},
          {"cameras_accepted", accepted},
          {"reprojection_rms_px", result.reprojection_rms_px},
          {"reprojection_rms_definition", "2-D error length per observation"},
          {"wand_length_error", LengthJson(result.wand_length)},
          {"rating", CalibrationRatingName(rig.rating)},
          {"rating_thresholds", thresholds.ToJson()},
          {"solver_iterations", result.solver_iterations},
          {"seconds", result.select_seconds + result.initialize_seconds + result.bundle_seconds},
          {"cameras", cameras}};
}

nlohmann::json WandReportFigures(const WandCalibrationResult& result, const WandGeometry& wand,
                                 const RatingThresholds& thresholds, const std::string& title) {
  nlohmann::json figures = WandResultJson(result, wand, thresholds);
  figures["title"] = title;
  figures["version"] = 1;
  const WandCalibrationFigures& f = result.figures;
  const Eigen::Matrix3d plot_from_world = PlotFromWorld(result.rig);
  for (size_t i = 0; i < result.cameras.size(); ++i) {
    nlohmann::json& camera = figures["cameras"][i];
    camera["residuals"] = ResidualJson(i < f.residuals_px.size() ? f.residuals_px[i] : std::vector<float>{});
    camera["coverage_map"] = {{"columns", f.coverage_grid},
                              {"rows", f.coverage_grid},
                              {"counts", i < f.coverage.size() ? f.coverage[i] : std::vector<uint32_t>{}}};
    if (const Camera* solved = result.rig.Find(result.cameras[i].id)) {
      camera["position"] = Vec(plot_from_world * solved->CenterInWorld());
      camera["direction"] = Vec(plot_from_world * solved->rotation.transpose() * Eigen::Vector3d::UnitZ());
    }
  }
  const std::vector<double>& errors = f.wand_length_errors_mm;
  std::vector<double> magnitudes;
  for (double e : errors) magnitudes.push_back(std::abs(e));
  const double reach = std::max(Quantile(magnitudes, 0.99) * 1.05, 0.01);
  const int bins = 41;
  figures["wand_length_histogram"] = Histogram(errors, -reach, 2.0 * reach / bins, bins);
  nlohmann::json path = nlohmann::json::array();
  const size_t step = f.wand_centres.size() / 600 + 1;
  for (size_t k = 0; k < f.wand_centres.size(); k += step) {
    const Eigen::Vector3d p = plot_from_world * f.wand_centres[k];
    path.push_back({std::round(p.x()), std::round(p.y()), std::round(p.z())});
  }
  figures["layout"] = {{"frame", "mm; z up along the mean of the cameras' image-up directions, x along the first "
                                 "camera's image rows (levelled); origin as the calibration's"},
                       {"wand_centres", path}};
  return figures;
}

nlohmann::json WandCalibrationDocument(const WandCalibrationResult& result, const nlohmann::json& report) {
  nlohmann::json document = RigToJson(result.rig);
  for (auto& camera : document["cameras"]) {
    for (const auto& c : result.cameras) {
      if (c.id == camera["id"].get<uint32_t>()) {
        camera["reprojection_rms_px"] = c.reprojection_rms_px;
        camera["wand_views"] = c.views_used;
        camera["coverage"] = c.coverage;
      }
    }
  }
  document["calibration"] = report;
  return document;
}

std::string WandReportHtml(const nlohmann::json& figures) {
  // '<' escaped inside the JSON, so that no text in it can close the script element.
  std::string data = figures.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  std::string escaped;
  escaped.reserve(data.size());
  for (char c : data) {
    if (c == '<') {
      escaped += "\\u003c";
    } else {
      escaped += c;
    }
  }
  std::string title = figures.value("title", std::string("wand calibration"));
  std::string safe_title;
  for (char c : title) safe_title += (c == '<' || c == '>' || c == '&') ? '_' : c;
  return "<!doctype html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>Wand calibration: " +
         safe_title +
         "</title>\n<style>\n"
         "body { font: 14px/1.4 system-ui, sans-serif; margin: 1.5em; color: #1d232a; }\n"
         "table { border-collapse: collapse; margin: 0.5em 0 1em; }\n"
         "th, td { border-bottom: 1px solid #d6dbe0; padding: 3px 8px; text-align: right; }\n"
         "th:first-child, td:first-child { text-align: left; }\n"
         ".plots { display: flex; flex-wrap: wrap; gap: 1.5em; }\n"
         "figure { margin: 0; } figcaption { font-weight: 600; margin-bottom: 4px; }\n"
         "</style>\n</head>\n<body>\n<div id=\"report\"><noscript>This report draws its plots with JavaScript; the "
         "figures are in figures.json beside it.</noscript></div>\n"
         "<script type=\"application/json\" id=\"figures\">" +
         escaped +
         "</script>\n<script type=\"module\">\n" + kCalibrationPlotsJs +
         "\nrenderWandReport(document.getElementById('report'), "
         "JSON.parse(document.getElementById('figures').textContent));\n</script>\n</body>\n</html>\n";
}

void WriteWandReport(const nlohmann::json& figures, const std::string& html_path, const std::string& json_path) {
  WriteJsonFile(figures, json_path, -1);
  WriteTextFile(WandReportHtml(figures), html_path);
}

}  // namespace mocap
