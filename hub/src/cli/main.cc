// mocap-hub: one executable, a table of sub-commands (COLMAP-style). Every failure ends as one
// line on stderr and the exit status of the policy in cli/commands.h; --help works on every level.
#include <cstdio>
#include <exception>
#include <string>

#include <CLI/CLI.hpp>

#include "cli/commands.h"
#include "util/log.h"

namespace {

// One line per command; the order is the order of `mocap-hub --help`.
using AddCommand = void (*)(CLI::App&);
const AddCommand kCommands[] = {
    mocap::AddServeCommand,
    mocap::AddServiceClientCommands,
    mocap::AddRecordCommand,
    mocap::AddKeysCommands,
    mocap::AddTokensCommands,
    mocap::AddSimRigCommand,
    mocap::AddSimProjectCommand,
    mocap::AddSimRenderCommand,
    mocap::AddSimMotionCommand,
    mocap::AddEvalCommand,
    mocap::AddReconstructCommand,
    mocap::AddProcessCommand,
    mocap::AddConvertCommand,
    mocap::AddArchiveCommand,
    mocap::AddRegisterCommand,
    mocap::AddMeshDriveCommand,
    mocap::AddBodyCommands,
    mocap::AddLabelsCommands,
    mocap::AddEditCommands,
    mocap::AddSkeletonCommands,
    mocap::AddBenchCommand,
    mocap::AddSimWandCommand,
    mocap::AddCalibrateWandCommand,
    mocap::AddCalibrateWorldCommand,
    mocap::AddCalibrateRefineCommand,
    mocap::AddCalibrateTargetCommands,
    mocap::AddSimTargetImageCommand,
    mocap::AddCalibrateIntrinsicsCommand,
    mocap::AddCalibrateDltCommand,
    mocap::AddCalibrateTsaiCommands,
    mocap::AddCalibrateMarkerCommand,
    mocap::AddCalibrateImportTsaiCommand,
    mocap::AddCalibrateImportMcdCommand,
    mocap::AddEvalCalibrationCommand,
};

struct GroupEntry {
  const char* name;
  const char* description;
};

const GroupEntry kGroups[] = {
    {"sim", "Simulator: motions, rigs, projected sessions with realistic faults, camera frames, wand waves"},
    {"keys", "Wire keys of the nodes: generate, rotate, retire, list (one file per node, mode 0600)"},
    {"mesh", "Meshes driven by markers: bind an OBJ to a static frame, export the motion as a point cache"},
    {"labels", "Marker sets: learn a labelling template from named trials, name anonymous markers with it"},
    {"skeleton", "Skeletons: templates from marker sets, subject calibration, per-frame solve to BVH, ASF/AMC and .mot"},
    {"calibrate", "Camera calibration: wand extrinsics, world frame, refinement from captures, intrinsics, DLT, Tsai, merging and seed-format imports"},
    {"edit", "Trajectory editor: apply an edit log (fills, swaps, splits, joins, renames, deletions, spikes) to a processed result"},
    {"body", "Rigid bodies: define one from a capture's markers, list a bodies file"},
    {"tokens", "API tokens for serve's HTTP API and console: issue (or rotate), revoke, list"},
};

}  // namespace

namespace mocap {

CLI::App& CommandGroup(CLI::App& app, const std::string& name) {
  for (CLI::App* existing : app.get_subcommands({})) {
    if (existing->get_name() == name) return *existing;
  }
  std::string description;
  for (const GroupEntry& group : kGroups)
    if (name == group.name) description = group.description;
  // Every group says what it is for in `mocap-hub --help` (a new one is named above).
  if (description.empty()) throw std::logic_error("command group '" + name + "' has no description in kGroups");
  CLI::App* group = app.add_subcommand(name, description);
  group->require_subcommand(1);
  return *group;
}

}  // namespace mocap

int main(int argc, char** argv) {
  CLI::App app{"mocap-hub: serve, record, reconstruct, calibrate, simulate and evaluate optical marker motion capture"};
  app.require_subcommand(1);
  app.fallthrough();  // --log-level is accepted after the command name too
  mocap::log::SetLevel(mocap::log::Level::kInfo);
  app.add_option_function<std::string>(
         "--log-level", [](const std::string& name) { mocap::log::SetLevel(*mocap::log::ParseLevel(name)); },
         "Diagnostics on stderr: trace, debug, info, warn, error or off")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "warning", "error", "off"}))
      ->default_str("info");
  for (AddCommand add : kCommands) add(app);
  // CLI11 would only say "a subcommand is required" for a misspelt command; name it instead.
  if (argc > 1 && argv[1][0] != '-') {
    bool known = false;
    for (const CLI::App* command : app.get_subcommands({})) known = known || command->get_name() == argv[1];
    if (!known) {
      std::fprintf(stderr, "mocap-hub: error: unknown command '%s' (see --help)\n", argv[1]);
      return 2;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    if (error.get_exit_code() == 0) return app.exit(error);  // --help, --version
    std::fprintf(stderr, "mocap-hub: error: %s (see --help)\n", error.what());
    return 2;
  } catch (const mocap::UsageError& error) {
    std::fprintf(stderr, "mocap-hub: error: %s (see --help)\n", error.what());
    return 2;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "mocap-hub: error: %s\n", error.what());
    return 1;
  }
  return 0;
}
