// `calibrate wand`'s report on the terminal (shared by the offline solve and the live one) and
// its live mode: a client of serve's wanding API (POST /api/calibration/wand/start, polling GET
// /api/calibration/wand for each camera's samples, coverage and advice until serve stops and
// solves, then the rated report, the files fetched from the recorded session and, when asked,
// POST .../apply).
//
// Threads: the caller's. Error policy: throws std::runtime_error with serve's reason (or
// UsageError for bad arguments); a solve that refuses cameras throws unless allow_partial.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace mocap {

// The per-camera table with ratings and the named rating limits (report: WandResultJson).
void PrintWandReport(const nlohmann::json& report);
// "ratings: reprojection RMS Exceptional <= 0.2 px, ...; ..." from RatingThresholds::ToJson().
std::string RatingRule(const nlohmann::json& thresholds);

struct LiveWandingArgs {
  std::string api;
  std::string session;        // the recording's name in serve's sessions directory
  nlohmann::json start;       // the start request's body without "name"
  std::string output;         // copy of the solved calibration ("" = none)
  std::string report_dir;     // wand_report.html and wand_figures.json ("" = none)
  bool apply = false;         // switch serve's live reconstruction to it
  bool save = false;          // ... and write it over serve's --calibration
  bool allow_partial = false;
  bool json = false;          // progress and report as JSON lines
  double poll_s = 0.5;
  double solve_wait_s = 900.0;  // the longest wait for serve's solve
};

void RunLiveWanding(const LiveWandingArgs& args);

}  // namespace mocap
