// `labels learn`: a marker set (labelling template) from labelled trials, and `labels apply`: names
// for an anonymous marker file from a marker set (what reconstruct --labels does to its output).
//   labels learn TRIAL.trc|.c3d... -o SET.json [--rigid-sd-mm S] [--up x|y|z|auto]
//   labels apply IN.trc|.c3d --labels SET.json -o OUT.trc|.c3d [--up x|y|z|auto] [--labeller trial|subject]
//                [--explain LOG]
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "cli/labels_helpers.h"
#include "io/trajectory_file.h"
#include "labels/marker_set_learning.h"

namespace mocap {
namespace {

struct LabelsLearnArgs {
  std::vector<std::string> trials;
  std::string output;
  MarkerSetLearnOptions options;
};

void RunLabelsLearn(const LabelsLearnArgs& args) {
  CheckOptions(args.options);
  std::vector<MarkerTrajectories> trials;
  for (const std::string& path : args.trials) trials.push_back(ReadTrajectories(path));
  MarkerSet set;
  try {
    set = LearnMarkerSet(trials, args.trials, args.options);
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error(error.what());
  }
  WriteMarkerSetFile(set, args.output);
  size_t in_segments = 0;
  for (const auto& s : set.segments) in_segments += s.size();
  std::printf("%s: %zu markers, %zu segments (%zu markers in them), %zu distances, from %zu trial(s)\n",
              args.output.c_str(), set.NumMarkers(), set.segments.size(), in_segments, set.distances.size(),
              trials.size());
}

struct LabelsApplyArgs {
  std::string input, labels, output;
  int up_axis = -1;
  LabellerChoice labeller;
};

void RunLabelsApply(const LabelsApplyArgs& args) {
  try {
    OutputTrajectoryFormatOf(args.output);
  } catch (const std::invalid_argument& error) {
    throw UsageError(error.what());
  }
  MarkerTrajectories markers = ReadTrajectories(args.input);
  const std::string report = NameTakeFromFile(args.labels, args.up_axis, &markers, args.labeller);
  WriteTrajectories(markers, args.output);
  std::printf("%s: %s\n", args.output.c_str(), report.c_str());
}

}  // namespace

void AddLabelsCommands(CLI::App& app) {
  CLI::App& labels = CommandGroup(app, "labels");
  {
    CLI::App* command = labels.add_subcommand("learn", "A marker set (labelling template) from labelled trials");
    auto args = std::make_shared<LabelsLearnArgs>();
    command->add_option("trials", args->trials, "Labelled marker files (.trc or .c3d with names)")
        ->required()
        ->check(CLI::ExistingFile);
    command->add_option("-o,--output", args->output, "Marker set to write (JSON)")->required();
    command->add_option("--rigid-sd-mm", args->options.rigid_sd_mm,
                        "Markers whose distances vary less than this (sd) form a segment")
        ->capture_default_str();
    AddUpAxisOption(*command, &args->options.up_axis, true, "Vertical axis of the trials: x, y, z or auto");
    command->callback([args] { RunLabelsLearn(*args); });
  }
  {
    CLI::App* command = labels.add_subcommand("apply", "Names for an anonymous marker file from a marker set");
    auto args = std::make_shared<LabelsApplyArgs>();
    command->add_option("input", args->input, "Marker file (.trc or .c3d)")->required()->check(CLI::ExistingFile);
    command->add_option("--labels", args->labels, "Marker set (labels learn)")->required()->check(CLI::ExistingFile);
    command->add_option("-o,--output", args->output, "Named marker file: .trc or .c3d")->required();
    AddUpAxisOption(*command, &args->up_axis, true, "Vertical axis of the data: x, y, z or auto (detected)");
    AddLabellerOptions(*command, &args->labeller, "--explain");
    command->callback([args] { RunLabelsApply(*args); });
  }
}

}  // namespace mocap
