// One session's reconstruction as `reconstruct` runs it, for the commands that run it
// (`reconstruct`, and `process` once per session of a batch): the calibration checked against the
// session's blobs, the offline chain
// (pipeline/offline_reconstruction.h) into OUTPUT, then the whole-take steps
// (pipeline/take_outputs.h), printing one summary line per step to stdout.
// Errors: UsageError for options out of range, std::runtime_error for files and data.
#pragma once

#include <string>

#include "bodies/body_live_filter.h"
#include "bodies/body_smoothing.h"
#include "calib/calibration_fit.h"
#include "cli/labels_helpers.h"
#include "pipeline/offline_reconstruction.h"

namespace mocap {

struct ReconstructArgs {
  std::string session;
  std::string calibration;  // empty: the session's own (SessionCalibration)
  bool force_calibration = false;  // reconstruct with a calibration that does not fit (a warning)
  CalibrationFitOptions fit;
  std::string output;  // .trc or .c3d
  std::string matcher = "relaxation";
  std::string assignment = "optimal";
  bool no_predictions = false;
  bool no_time_align = false;  // free-run sessions: leave each camera's blobs at its own instant
  pipeline::OfflineReconstructionOptions chain;
  std::string bodies;  // rigid bodies file; empty: none
  BodySmoothingOptions body_smoothing;
  bool bodies_live = false;  // the live (causal) body path instead of the offline one
  BodyLiveFilterOptions body_filter;
  std::string labels;  // marker set; empty: anonymous columns
  LabellerChoice labeller;  // which whole-take labeller names, and its decision log
  std::string known_correspondences;  // truth TRC: write the known-correspondence floor instead
  bool progress = true;  // a progress bar on stderr when it is a terminal
  std::string progress_file;  // also the progress as JSON there (cli/progress.h); empty: none
};

// The calibration kept with a session: the file its session.json names, inside its directory.
// std::runtime_error when that name is not a plain file name or the file is missing.
std::string SessionCalibration(const std::string& session);

// Before reconstructing, a sample of the session's frame sets judges the calibration
// (calib/calibration_fit.h); one that does not fit is refused (std::runtime_error with every
// camera's median residual) unless force_calibration, which reconstructs with a warning.
void ReconstructSession(ReconstructArgs args);

}  // namespace mocap
