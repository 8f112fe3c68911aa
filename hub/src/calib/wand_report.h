// The wand calibration report: the solver's result as one JSON document of figures (per camera
// rating, residual histogram, coverage map, position and viewing direction; the wand-length error
// histogram; the wand's path) and as a self-contained HTML page drawing them as SVG plots with
// the console's own plotting module (hub/web/js/calibration_plots.js, built into the binary), so
// the page needs no network, no plotting package and opens in any browser.
//
// Threads: none. Error policy: writing throws std::runtime_error "<path>: <what>"
// (util/json_file.h); building the figures never throws on a valid result.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "calib/wand_calibration.h"
#include "calib/wand_observations.h"
#include "calib/wand_quality.h"

namespace mocap {

// The report's numbers, as `calibrate wand --json` prints them: frames, residuals, wand length
// error and per camera acceptance, with each camera's rating.
nlohmann::json WandResultJson(const WandCalibrationResult& result, const WandGeometry& wand,
                              const RatingThresholds& thresholds);

// WandResultJson plus everything the plots need. `title` names the session.
nlohmann::json WandReportFigures(const WandCalibrationResult& result, const WandGeometry& wand,
                                 const RatingThresholds& thresholds, const std::string& title);

// The calibration document `calibrate wand` writes: the rig (accepted cameras), per camera its
// residual, views and coverage, and `report` (WandResultJson) under "calibration".
nlohmann::json WandCalibrationDocument(const WandCalibrationResult& result, const nlohmann::json& report);

// The HTML page for these figures (the figures are embedded, nothing is loaded).
std::string WandReportHtml(const nlohmann::json& figures);

// Writes html_path and json_path (each atomically).
void WriteWandReport(const nlohmann::json& figures, const std::string& html_path, const std::string& json_path);

}  // namespace mocap
