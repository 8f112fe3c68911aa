// The naming step shared by `reconstruct --labels` and `labels apply`: reads the marker set and
// names the take in place (pipeline/take_outputs.h) with the labeller chosen; returns the one-line
// report. Errors (an unreadable set, a set that cannot label, an unwritable decision log):
// std::runtime_error naming the file; --explain without the subject labeller: UsageError.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "io/marker_trajectories.h"

namespace mocap {

struct LabellerChoice {
  std::string labeller = "trial";  // "trial" (labels/trial_labeller.h) or "subject" (labels/subject_labeller.h)
  std::string explain;             // file for the subject labeller's decisions, one line each; empty: none
};

// --labeller and the decision log's option (`explain_flag`, e.g. "--explain") on `command`.
void AddLabellerOptions(CLI::App& command, LabellerChoice* choice, const std::string& explain_flag);

// up_axis: 0-2, or -1 to detect it from the data.
std::string NameTakeFromFile(const std::string& marker_set_path, int up_axis, MarkerTrajectories* markers,
                             const LabellerChoice& choice = {});

}  // namespace mocap
