// The mocap-hub command table's entries. Each Add*Command registers one sub-command on the root
// app (group commands such as "sim ..." go through CommandGroup) and gives it a callback that
// does the work. Error policy of the CLI: callbacks validate their inputs and throw
// std::runtime_error / std::invalid_argument with a one-line reason; main() prints
// "mocap-hub: error: <reason>" to stderr and exits 1. Results go to stdout, progress to stderr.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

namespace mocap {

// The sub-command `name` of `app` (created on first use, requiring one sub-command of its own),
// so that several files can add commands to one group ("sim rig", "sim wand", "calibrate wand").
CLI::App& CommandGroup(CLI::App& app, const std::string& name, const std::string& description);

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
void AddBenchCommand(CLI::App& app);
void AddSimRenderCommand(CLI::App& app);
void AddSimWandCommand(CLI::App& app);
void AddCalibrateWandCommand(CLI::App& app);
void AddEvalCalibrationCommand(CLI::App& app);
// cmd_calibrate.cc (besides sim wand, calibrate wand and eval-calibration above)
void AddCalibrateWorldCommand(CLI::App& app);
void AddCalibrateIntrinsicsCommand(CLI::App& app);
void AddCalibrateDltCommand(CLI::App& app);
void AddCalibrateImportTsaiCommand(CLI::App& app);
void AddCalibrateImportMcdCommand(CLI::App& app);

}  // namespace mocap
