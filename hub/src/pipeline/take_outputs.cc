// The whole-take steps after the reconstruction (see take_outputs.h).
#include "pipeline/take_outputs.h"

#include <algorithm>
#include <map>
#include <utility>

#include <fmt/format.h>

#include "labels/subject_labeller.h"
#include "labels/trial_labeller.h"

namespace mocap::pipeline {

std::string TakeNaming::Describe() const {
  const std::string init = labeller == TakeLabeller::kSubject
                               ? fmt::format("initialised at frame {} with {} names; ", init_frame, init_names)
                               : std::string();
  return fmt::format("{} of {} names placed, {:.2f}% of points named ({} runs of {}; {}{} points unnamed in frames "
                     "that broke their distances)",
                     names_placed, set_markers,
                     points ? 100.0 * static_cast<double>(named_points) / static_cast<double>(points) : 0.0,
                     named_runs, runs, init, frame_names_dropped);
}

namespace {

template <typename Labelling>
TakeNaming Counts(const MarkerSet& set, Labelling* result, MarkerTrajectories* markers) {
  *markers = std::move(result->named);
  TakeNaming naming;
  naming.names_placed = result->names_placed;
  naming.set_markers = set.NumMarkers();
  naming.named_points = result->named_points;
  naming.points = result->points;
  naming.named_runs = result->named_runs;
  naming.runs = result->runs;
  naming.frame_names_dropped = result->frame_names_dropped;
  return naming;
}

}  // namespace

TakeNaming NameTake(const MarkerSet& set, int up_axis, MarkerTrajectories* markers, TakeLabeller labeller) {
  const int up = up_axis >= 0 ? up_axis : DetectUpAxis(*markers);
  if (labeller == TakeLabeller::kTrial) {
    LabellerOptions options;
    options.up_axis = up;
    TrialLabelling result = LabelTrajectories(*markers, set, options);
    return Counts(set, &result, markers);
  }
  SubjectLabellerOptions options;
  options.up_axis = up;
  SubjectLabelling result = LabelSubject(*markers, set, options);
  TakeNaming naming = Counts(set, &result, markers);
  naming.labeller = TakeLabeller::kSubject;
  naming.init_frame = result.init_frame;
  naming.init_names = result.init_names;
  naming.decisions_made = result.decisions_made;
  naming.decisions = std::move(result.decisions);
  return naming;
}

size_t TakeBodies::FramesFitted(size_t body) const {
  size_t fitted = 0;
  for (const BodyPoseRow& row : rows) fitted += row.poses[body].tracked;
  return fitted;
}

std::string TakeBodies::MissSummary(size_t body) const {
  std::map<BodyMiss, size_t> frames;
  for (const BodyPoseRow& row : rows)
    if (!row.poses[body].tracked) ++frames[row.poses[body].miss];
  std::vector<std::pair<size_t, BodyMiss>> by_count;
  for (const auto& [miss, count] : frames) by_count.emplace_back(count, miss);
  std::stable_sort(by_count.begin(), by_count.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::string text;
  for (const auto& [count, miss] : by_count)
    text += (text.empty() ? "" : "; ") + std::to_string(count) + " frames: " + BodyMissText(miss);
  return text;
}

TakeBodies FitTakeBodies(const std::vector<RigidBodyDefinition>& bodies, const BodySmoothingOptions& smoothing,
                         MarkerTrajectories* markers) {
  TakeBodies take;
  take.rows = TrackBodies(*markers, bodies, {}, smoothing, &take.smoothing);
  AddVirtualMarkers(markers, bodies, take.rows);
  return take;
}

}  // namespace mocap::pipeline
