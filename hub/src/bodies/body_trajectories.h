// Rigid bodies over a whole recording (reconstruct --bodies): the tracker run over every frame of
// a marker file's points (taken as anonymous: identity comes from the bodies' shapes), then each
// body's orientations refined over neighbouring frames (body_smoothing.h), the poses as a
// tab-separated file, and one virtual marker per body (its pivot) for TRC/C3D.
// Pose file columns: frame (the file's Frame#, 1-based), time_s, body, tracked, predicted,
// x, y, z (the pivot, mm), qx, qy, qz, qw (body -> world), mean_error_mm, markers; one row per
// body and frame. Errors: std::runtime_error "<file>: <reason>".
#pragma once

#include <string>
#include <vector>

#include "bodies/body_smoothing.h"
#include "bodies/body_tracker.h"
#include "io/marker_trajectories.h"

namespace mocap {

struct BodyPoseRow {
  uint64_t frame_number = 0;
  std::vector<BodyPose> poses;  // one per body
};

// `stats`, when given, gets one entry per body: what the smoothing did.
std::vector<BodyPoseRow> TrackBodies(const MarkerTrajectories& markers, const std::vector<RigidBodyDefinition>& bodies,
                                     const BodyTrackerOptions& options = {},
                                     const BodySmoothingOptions& smoothing = {},
                                     std::vector<BodySmoothingStats>* stats = nullptr);

// Appends a column per body named after it: its pivot where fitted or predicted, else a gap.
void AddVirtualMarkers(MarkerTrajectories* markers, const std::vector<RigidBodyDefinition>& bodies,
                       const std::vector<BodyPoseRow>& rows);

void WriteBodyPoses(const std::string& path, const std::vector<RigidBodyDefinition>& bodies,
                    const std::vector<BodyPoseRow>& rows, double rate_hz);

// One row of a pose file as read back (eval --bodies-truth/--bodies-result).
struct BodyPoseRecord {
  uint64_t frame = 0;  // the file's frame column (1-based)
  std::string body;
  bool tracked = false, predicted = false;
  Eigen::Vector3d pivot = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  double mean_error_mm = 0.0;
  size_t markers = 0;
};

// Reads a pose file written by WriteBodyPoses (reconstruct --bodies, sim project --bodies).
// Throws std::runtime_error "<source>: line N: <reason>" for anything else.
std::vector<BodyPoseRecord> ParseBodyPoses(const std::string& text, const std::string& source);
std::vector<BodyPoseRecord> ReadBodyPoses(const std::string& path);

}  // namespace mocap
