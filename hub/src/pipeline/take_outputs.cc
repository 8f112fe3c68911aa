// The whole-take steps after the reconstruction (see take_outputs.h).
#include "pipeline/take_outputs.h"

#include <utility>

#include <fmt/format.h>

#include "labels/trial_labeller.h"

namespace mocap::pipeline {

std::string TakeNaming::Describe() const {
  return fmt::format("{} of {} names placed, {:.2f}% of points named ({} runs of {}; {} points unnamed in frames "
                     "that broke their distances)",
                     names_placed, set_markers,
                     points ? 100.0 * static_cast<double>(named_points) / static_cast<double>(points) : 0.0,
                     named_runs, runs, frame_names_dropped);
}

TakeNaming NameTake(const MarkerSet& set, int up_axis, MarkerTrajectories* markers) {
  LabellerOptions options;
  options.up_axis = up_axis >= 0 ? up_axis : DetectUpAxis(*markers);
  TrialLabelling result = LabelTrajectories(*markers, set, options);
  *markers = std::move(result.named);
  TakeNaming naming;
  naming.names_placed = result.names_placed;
  naming.set_markers = set.NumMarkers();
  naming.named_points = result.named_points;
  naming.points = result.points;
  naming.named_runs = result.named_runs;
  naming.runs = result.runs;
  naming.frame_names_dropped = result.frame_names_dropped;
  return naming;
}

size_t TakeBodies::FramesFitted(size_t body) const {
  size_t fitted = 0;
  for (const BodyPoseRow& row : rows) fitted += row.poses[body].tracked;
  return fitted;
}

TakeBodies FitTakeBodies(const std::vector<RigidBodyDefinition>& bodies, const BodySmoothingOptions& smoothing,
                         MarkerTrajectories* markers) {
  TakeBodies take;
  take.rows = TrackBodies(*markers, bodies, {}, smoothing, &take.smoothing);
  AddVirtualMarkers(markers, bodies, take.rows);
  return take;
}

}  // namespace mocap::pipeline
