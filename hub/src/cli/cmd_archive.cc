// `archive`: a session's (or a marker file's) trajectories PCA-compressed into a .mca archive
// (archive/), whole body or per marker-set segment, components fixed or chosen by an error bound;
// prints the size against the input's and the error measured on the decoded archive.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "archive/archive_format.h"
#include "archive/trajectory_pca.h"
#include "cli/commands.h"
#include "io/trajectory_file.h"
#include "labels/marker_set.h"

namespace mocap {
namespace {

struct ArchiveArgs {
  std::string input, output, marker_set;
  TrajectoryPcaOptions options;
  bool json = false;
};

// A session directory's markers.trc, or the marker file itself.
std::string MarkerFileOf(const std::string& input) {
  if (!std::filesystem::is_directory(input)) return input;
  const std::string path = (std::filesystem::path(input) / "markers.trc").string();
  if (!std::filesystem::exists(path))
    throw std::runtime_error(input + ": session has no markers.trc (reconstruct it first)");
  return path;
}

// The marker set's segments as groups of this recording's markers; markers in no segment form one
// more group.
std::vector<std::vector<int>> SegmentGroups(const MarkerTrajectories& motion, const std::string& path) {
  const MarkerSet set = ReadMarkerSetFile(path);
  std::vector<std::vector<int>> groups;
  std::vector<bool> grouped(motion.NumMarkers(), false);
  for (const std::vector<int>& segment : set.segments) {
    std::vector<int> group;
    for (int member : segment)
      for (size_t m = 0; m < motion.NumMarkers(); ++m)
        if (!grouped[m] && motion.names[m] == set.names[static_cast<size_t>(member)]) {
          group.push_back(static_cast<int>(m));
          grouped[m] = true;
        }
    if (!group.empty()) groups.push_back(std::move(group));
  }
  std::vector<int> rest;
  for (size_t m = 0; m < motion.NumMarkers(); ++m)
    if (!grouped[m]) rest.push_back(static_cast<int>(m));
  if (!rest.empty()) groups.push_back(std::move(rest));
  return groups;
}

void RunArchive(const ArchiveArgs& args) {
  CheckOptions(args.options);
  if (!IsArchivePath(args.output)) throw UsageError("-o: '" + args.output + "' must end in .mca");
  const std::string input = MarkerFileOf(args.input);
  const MarkerTrajectories motion = ReadTrajectories(input);
  const std::vector<std::vector<int>> groups =
      args.marker_set.empty() ? std::vector<std::vector<int>>{} : SegmentGroups(motion, args.marker_set);
  CompressedTrajectories compressed;
  try {
    compressed = CompressTrajectories(motion, groups, args.options);
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error(input + ": " + error.what());
  }
  WriteArchiveFile(compressed, args.output);
  // The error as a reader will see it: the file read back and expanded.
  const MarkerTrajectories decoded = DecompressTrajectories(ReadArchiveFile(args.output));
  const double rms = TrajectoryRmsError(motion, decoded);
  double worst = 0.0;
  for (size_t i = 0; i < motion.points.size(); ++i)
    if (!MarkerTrajectories::IsGap(motion.points[i]))
      worst = std::max(worst, (motion.points[i] - decoded.points[i]).norm());
  double components = 0.0;
  for (const PcaBlock& block : compressed.blocks) components += block.components;
  components /= static_cast<double>(compressed.blocks.size());
  const uintmax_t archive_bytes = std::filesystem::file_size(args.output);
  const uintmax_t input_bytes = std::filesystem::file_size(input);
  const double ratio = static_cast<double>(input_bytes) / static_cast<double>(archive_bytes);
  if (args.json) {
    const nlohmann::json out = {{"archive", args.output}, {"input", input}, {"markers", motion.NumMarkers()},
                                {"frames", motion.NumFrames()}, {"groups", compressed.groups.size()},
                                {"windows", compressed.NumWindows()}, {"mean_components", components},
                                {"archive_bytes", archive_bytes}, {"input_bytes", input_bytes}, {"ratio", ratio},
                                {"rms_mm", rms}, {"max_mm", worst}};
    std::printf("%s\n", out.dump().c_str());
  } else {
    std::printf("%s: %zu markers, %zu frames, %zu group(s) x %zu window(s), %.1f components on average\n",
                args.output.c_str(), motion.NumMarkers(), motion.NumFrames(), compressed.groups.size(),
                compressed.NumWindows(), components);
    std::printf("%ju bytes, %.1fx smaller than %s (%ju bytes); error %.3f mm RMS, %.3f mm at most\n", archive_bytes,
                ratio, input.c_str(), input_bytes, rms, worst);
  }
}

}  // namespace

void AddArchiveCommand(CLI::App& app) {
  CLI::App* command = app.add_subcommand(
      "archive", "Compress a session's trajectories (PCA per window, quantised; gaps kept) into a .mca archive");
  auto args = std::make_shared<ArchiveArgs>();
  command->add_option("input", args->input, "Session directory (its markers.trc) or marker file (.trc, .c3d)")
      ->required()
      ->check(CLI::ExistingPath);
  command->add_option("-o,--output", args->output, "Archive to write (.mca)")->required();
  command->add_option("--components", args->options.components,
                      "Components per window and group (1-255); default: as few as --max-error-mm allows");
  command->add_option("--max-error-mm", args->options.max_error_mm,
                      "RMS 3D error bound per window and group, mm (when --components is not given)")
      ->check(FiniteRange(1e-6, 1e6));
  command->add_option("--window-frames", args->options.window_frames, "Frames per PCA window (1-4096)");
  command->add_option("--marker-set", args->marker_set,
                      "Marker set (labels learn) whose segments are compressed separately; default: whole body")
      ->check(CLI::ExistingFile);
  command->add_flag("--json", args->json, "Print one JSON object");
  command->callback([args] { RunArchive(*args); });
}

}  // namespace mocap
