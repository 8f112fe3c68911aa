// `edit apply LOG --input IN -o OUT` and `edit spikes --input IN`: the trajectory editor's edit
// log applied to a processed result (edit/edit_apply.h), never in place: OUT and its
// OUT-stem.filled.tsv are new files. Every sample of IN counts as measured.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "edit/edit_apply.h"
#include "edit/edit_output.h"
#include "io/trajectory_file.h"

namespace mocap {
namespace {

edit::EditedTake ReadTake(const std::string& input) {
  try {
    TrajectoryFormatOf(input);
  } catch (const std::invalid_argument& error) {
    throw UsageError(std::string("--input: ") + error.what());
  }
  return edit::EditedTake::FromMeasured(ReadTrajectories(input));
}

nlohmann::json SpikesJson(const edit::EditReport& report) {
  nlohmann::json spikes = nlohmann::json::array();
  for (const auto& s : report.spikes)
    spikes.push_back({{"marker", s.marker},
                      {"frame", s.frame},
                      {"accel_mm_per_frame2", s.accel_mm_per_frame2},
                      {"limit_mm_per_frame2", s.limit_mm_per_frame2},
                      {"removed", s.removed}});
  return spikes;
}

void AddApply(CLI::App& group) {
  CLI::App* command = group.add_subcommand("apply", "Apply an edit log to a processed result, writing a new file and its .filled.tsv");
  struct Args {
    std::string log, input, output;
    bool json = false;
  };
  auto args = std::make_shared<Args>();
  command->add_option("log", args->log, "Edit log (JSON, docs/editor.md)")->required()->check(CLI::ExistingFile);
  command->add_option("--input", args->input, "Processed result to edit (.trc or .c3d); never written")->required()->check(CLI::ExistingFile);
  command->add_option("-o,--output", args->output, "Edited result (.trc or .c3d; C3D residuals mark filled samples)")->required();
  command->add_flag("--json", args->json, "Print one JSON object on stdout");
  command->callback([args] {
    try {
      TrajectoryFormatOf(args->output);
    } catch (const std::invalid_argument& error) {
      throw UsageError(std::string("--output: ") + error.what());
    }
    std::error_code ec;
    if (std::filesystem::equivalent(args->input, args->output, ec))
      throw UsageError("--output: " + args->output + " is the input; edits never overwrite a result");
    const edit::EditLog log = edit::ReadEditLog(args->log);
    edit::EditedTake take = ReadTake(args->input);
    edit::EditReport report;
    try {
      report = edit::ApplyEdits(log, &take);
    } catch (const std::invalid_argument& error) {
      throw std::runtime_error(args->log + ": " + error.what());
    }
    edit::WriteEditedTake(take, args->output);
    size_t filled = 0, present = 0;
    for (size_t i = 0; i < take.marks.size(); ++i)
      if (!MarkerTrajectories::IsGap(take.markers.points[i])) ++present, filled += take.marks[i] != 0;
    if (args->json) {
      const nlohmann::json out = {{"output", args->output},
                                  {"filled_file", edit::FilledSidePath(args->output)},
                                  {"operations", report.lines},
                                  {"spikes", SpikesJson(report)},
                                  {"samples", present},
                                  {"filled_samples", filled}};
      std::printf("%s\n", out.dump().c_str());
      return;
    }
    for (const std::string& line : report.lines) std::printf("%s\n", line.c_str());
    std::printf("%s: %zu markers, %zu frames, %zu of %zu samples filled (%s)\n", args->output.c_str(),
                take.markers.NumMarkers(), take.markers.NumFrames(), filled, present,
                edit::FilledSidePath(args->output).c_str());
  });
}

void AddSpikes(CLI::App& group) {
  CLI::App* command = group.add_subcommand("spikes", "List samples whose acceleration is an outlier (nothing is written)");
  struct Args {
    std::string input;
    std::vector<std::string> markers;
    double threshold = 8.0;
    bool json = false;
  };
  auto args = std::make_shared<Args>();
  command->add_option("--input", args->input, "Marker file (.trc or .c3d)")->required()->check(CLI::ExistingFile);
  command->add_option("--marker", args->markers, "Only these markers (repeatable; default all)");
  command->add_option("--threshold", args->threshold, "Robust z-score of the acceleration (median + T x 1.4826 MAD)")
      ->capture_default_str()
      ->check(FiniteRange(2.0, 1000.0));
  command->add_flag("--json", args->json, "Print one JSON object on stdout");
  command->callback([args] {
    edit::EditedTake take = ReadTake(args->input);
    edit::EditOperation op;
    op.kind = edit::EditKind::kSpikes;
    op.markers = args->markers;
    op.threshold = args->threshold;
    edit::EditReport report;
    try {
      edit::ApplyEdit(op, 0, &take, &report);
    } catch (const std::invalid_argument& error) {
      throw UsageError(std::string("--marker: ") + error.what());
    }
    if (args->json) {
      std::printf("%s\n", nlohmann::json({{"input", args->input}, {"spikes", SpikesJson(report)}}).dump().c_str());
      return;
    }
    for (const auto& s : report.spikes)
      std::printf("%s\t%llu\t%.3f mm/frame^2 (limit %.3f)\n", s.marker.c_str(), static_cast<unsigned long long>(s.frame),
                  s.accel_mm_per_frame2, s.limit_mm_per_frame2);
    std::printf("%zu spikes\n", report.spikes.size());
  });
}

}  // namespace

void AddEditCommands(CLI::App& app) {
  CLI::App& group = CommandGroup(app, "edit");
  AddApply(group);
  AddSpikes(group);
}

}  // namespace mocap
