// `convert IN OUT`: marker files between TRC and C3D (formats by extension), names, rate, frame
// numbers and gaps kept.
#include <cstdio>
#include <memory>
#include <string>

#include "cli/commands.h"
#include "io/trajectory_file.h"

namespace mocap {

void AddConvertCommand(CLI::App& app) {
  CLI::App* command = app.add_subcommand("convert", "Convert marker files between TRC and C3D (by extension)");
  struct Args {
    std::string input, output;
  };
  auto args = std::make_shared<Args>();
  command->add_option("input", args->input, "Marker file to read (.trc or .c3d)")->required()->check(CLI::ExistingFile);
  command->add_option("output", args->output, "Marker file to write (.trc or .c3d)")->required();
  command->callback([args] {
    try {
      TrajectoryFormatOf(args->input);
      TrajectoryFormatOf(args->output);
    } catch (const std::invalid_argument& error) {
      throw UsageError(error.what());
    }
    const MarkerTrajectories trajectories = ReadTrajectories(args->input);
    WriteTrajectories(trajectories, args->output);
    std::printf("%s: %zu markers, %zu frames at %g Hz\n", args->output.c_str(), trajectories.NumMarkers(),
                trajectories.NumFrames(), trajectories.rate_hz);
  });
}

}  // namespace mocap
