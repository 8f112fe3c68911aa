// The mocap-hub command table's entries. Each Add*Command registers one sub-command on the root
// app (group commands such as "sim ..." go through CommandGroup) and gives it a callback that
// does the work. Error policy of the CLI: callbacks validate their inputs and throw with a
// one-line reason; main() prints "mocap-hub: error: <reason>" to stderr and exits with
//   0 ok, 1 a runtime or input error (files, data, devices), 2 a usage error (CLI11's parse
//   errors, an unknown command, an option value out of range: UsageError, CheckOptions).
// Results go to stdout; diagnostics and progress to stderr (util/log.h).
#pragma once

#include <stdexcept>
#include <string>

#include <CLI/CLI.hpp>

#include "recon/recon_options.h"
#include "track/track_options.h"

namespace mocap {

// A command line that cannot be run as given (exit status 2).
class UsageError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// Runs an options struct's Check() (which throws std::invalid_argument, the hub's options policy)
// on options that came from the command line, so that a bad value is a usage error.
template <typename Options>
void CheckOptions(const Options& options) {
  try {
    options.Check();
  } catch (const std::invalid_argument& error) {
    throw UsageError(error.what());
  }
}

// --up: x, y or z in any case, and `auto` where allow_auto; parsed here once into an axis index
// (0, 1, 2; -1 for auto). *axis keeps its value when the option is not given.
CLI::Option* AddUpAxisOption(CLI::App& command, int* axis, bool allow_auto, const std::string& help);
// "x", "y", "z" or "auto", as the option is written.
std::string UpAxisName(int axis);
// A finite number within [lo, hi] (CLI::Range alone accepts NaN).
CLI::Validator FiniteRange(double lo, double hi);

// rig_options.cc: the options left once the gates follow the rig's centroid noise (the noise
// itself, views needed, the Kalman process noise, the rigid model's thresholds), shared by
// `reconstruct` and `serve` (and so hub.conf's keys of the same names).
void AddRigOptions(CLI::App& command, ReconstructorOptions* recon, TrackerOptions* tracker);

// The sub-command `name` of `app` (created on first use, requiring one sub-command of its own),
// so that several files can add commands to one group ("sim rig", "sim wand", "calibrate wand").
// Group descriptions live in one table in main.cc.
CLI::App& CommandGroup(CLI::App& app, const std::string& name);

// cmd_sim.cc
void AddSimRigCommand(CLI::App& app);
void AddSimProjectCommand(CLI::App& app);
// cmd_sim_motion.cc
void AddSimMotionCommand(CLI::App& app);
// cmd_eval.cc
void AddEvalCommand(CLI::App& app);

// Commands of the other layers; each lives in its own cmd_<name>.cc.
void AddRecordCommand(CLI::App& app);
void AddReconstructCommand(CLI::App& app);
void AddProcessCommand(CLI::App& app);  // cmd_process.cc: a recipe applied to sessions
void AddBenchCommand(CLI::App& app);
void AddSimRenderCommand(CLI::App& app);
void AddSimWandCommand(CLI::App& app);
void AddCalibrateWandCommand(CLI::App& app);
void AddEvalCalibrationCommand(CLI::App& app);
void AddConvertCommand(CLI::App& app);
void AddArchiveCommand(CLI::App& app);    // cmd_archive.cc
void AddRegisterCommand(CLI::App& app);   // cmd_register.cc
void AddMeshDriveCommand(CLI::App& app);  // cmd_mesh.cc: mesh drive
void AddBodyCommands(CLI::App& app);
void AddLabelsCommands(CLI::App& app);  // cmd_labels.cc: labels learn, labels apply
void AddEditCommands(CLI::App& app);    // cmd_edit.cc: edit apply, edit spikes
void AddSkeletonCommands(CLI::App& app);  // cmd_skeleton.cc: skeleton template, calibrate, solve, sim, eval
// cmd_sim_wand.cc, cmd_calibrate_wand.cc (wand, world), cmd_calibrate_camera.cc (intrinsics,
// dlt), cmd_calibrate_import.cc (import-tsai, import-mcd), cmd_eval_calibration.cc.
void AddCalibrateWorldCommand(CLI::App& app);
void AddCalibrateRefineCommand(CLI::App& app);  // cmd_calibrate_refine.cc
// cmd_calibrate_target.cc: calibrate target, calibrate target-points; sim target-image.
void AddCalibrateTargetCommands(CLI::App& app);
void AddSimTargetImageCommand(CLI::App& app);
void AddCalibrateIntrinsicsCommand(CLI::App& app);
void AddCalibrateDltCommand(CLI::App& app);
void AddCalibrateTsaiCommands(CLI::App& app);  // calibrate tsai, calibrate merge
void AddCalibrateMarkerCommand(CLI::App& app);
void AddCalibrateImportTsaiCommand(CLI::App& app);
void AddCalibrateImportMcdCommand(CLI::App& app);
// cmd_serve.cc; cmd_service_clients.cc (status, nodes, node, mask, capture, sessions).
void AddServeCommand(CLI::App& app);
// cmd_keys.cc (keys new, rotate, retire, list).
void AddKeysCommands(CLI::App& app);
// cmd_tokens.cc (tokens new, revoke, list: the API's tokens).
void AddTokensCommands(CLI::App& app);
void AddServiceClientCommands(CLI::App& app);

}  // namespace mocap
