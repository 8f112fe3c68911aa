// Rigid bodies over a whole recording (reconstruct --bodies): the tracker run over every frame of
// a marker file's points (taken as anonymous: identity comes from the bodies' shapes), the poses
// as a tab-separated file, and one virtual marker per body (its pivot) for TRC/C3D.
// Pose file columns: frame (the file's Frame#, 1-based), time_s, body, tracked, predicted,
// x, y, z (the pivot, mm), qx, qy, qz, qw (body -> world), mean_error_mm, markers; one row per
// body and frame. Errors: std::runtime_error "<file>: <reason>".
#pragma once

#include <string>
#include <vector>

#include "bodies/body_tracker.h"
#include "io/marker_trajectories.h"

namespace mocap {

struct BodyPoseRow {
  uint64_t frame_number = 0;
  std::vector<BodyPose> poses;  // one per body
};

std::vector<BodyPoseRow> TrackBodies(const MarkerTrajectories& markers, const std::vector<RigidBodyDefinition>& bodies,
                                     const BodyTrackerOptions& options = {});

// Appends a column per body named after it: its pivot where fitted or predicted, else a gap.
void AddVirtualMarkers(MarkerTrajectories* markers, const std::vector<RigidBodyDefinition>& bodies,
                       const std::vector<BodyPoseRow>& rows);

void WriteBodyPoses(const std::string& path, const std::vector<RigidBodyDefinition>& bodies,
                    const std::vector<BodyPoseRow>& rows, double rate_hz);

}  // namespace mocap
