// `convert IN OUT`: marker files between TRC, C3D and .mca archives (formats by extension), names,
// rate, frame numbers and gaps kept (an archive's points within its error bound; one written
// here takes `archive`'s defaults).
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>

#include "archive/archive_format.h"
#include "cli/commands.h"
#include "io/trajectory_file.h"

namespace mocap {

void AddConvertCommand(CLI::App& app) {
  CLI::App* command = app.add_subcommand("convert", "Convert marker files between TRC, C3D and .mca archives (by extension)");
  struct Args {
    std::string input, output;
  };
  auto args = std::make_shared<Args>();
  command->add_option("input", args->input, "Marker file to read (.trc, .c3d or .mca)")->required()->check(CLI::ExistingFile);
  command->add_option("output", args->output, "Marker file to write (.trc, .c3d or .mca)")->required();
  command->callback([args] {
    const bool archive_in = IsArchivePath(args->input), archive_out = IsArchivePath(args->output);
    try {
      if (!archive_in) TrajectoryFormatOf(args->input);
      if (!archive_out) OutputTrajectoryFormatOf(args->output);
    } catch (const std::invalid_argument& error) {
      throw UsageError(std::string(error.what()) + " or .mca archives");
    }
    const MarkerTrajectories trajectories =
        archive_in ? DecompressTrajectories(ReadArchiveFile(args->input)) : ReadTrajectories(args->input);
    if (archive_out) {
      try {
        WriteArchiveFile(CompressTrajectories(trajectories, {}, TrajectoryPcaOptions{}), args->output);
      } catch (const std::invalid_argument& error) {
        throw std::runtime_error(args->input + ": " + error.what());
      }
    } else {
      WriteTrajectories(trajectories, args->output);
    }
    std::printf("%s: %zu markers, %zu frames at %g Hz\n", args->output.c_str(), trajectories.NumMarkers(),
                trajectories.NumFrames(), trajectories.rate_hz);
  });
}

}  // namespace mocap
