// Subject calibration: a template skeleton fitted to one person from a static or range-of-motion
// trial: every joint centre (functional: the centre about which the child segment's markers turn
// relative to the parent's, found by fitting the whole skeleton to many frames at once, as a
// sphere fit of each child's markers does joint by joint), segment lengths (a bone's length, the
// other joints' 3-D offsets) and each marker's offset on its segment.
// Steps: the template scaled to the subject's height; each frame of the window solved with it
// (warm-started); then one Ceres problem over up to `max_frames` frames: poses, joint offsets and
// marker offsets together (Huber loss on markers), first with every joint centre held at the
// template's; the window tracked again with that skeleton measures each joint's range; twice
// more the track and the fit with the centres of the joints that turned set free.
// Gauge: a segment whose frame neither a bone nor a hinge fixes (template "reference_zero":
// pelvis, trunk, head, feet, hands) takes its angles as zero in the window's first frame: the
// subject stands upright there (the pelvis only its tilt and roll; its heading is free).
// Refusals (std::invalid_argument naming what and why): a marker never seen in the window, a
// joint that turns less than `min_joint_range_deg` (its centre is then not determined by the
// trial) unless `keep_template_centres`, in which case that centre stays where the scaled template
// puts it and the report says so.
#pragma once

#include <string>
#include <vector>

#include "io/marker_trajectories.h"
#include "skeleton/skeleton.h"

namespace mocap {

struct SubjectCalibrationOptions {
  double start_s = 0.0;      // window start, seconds from the trial's first frame
  double duration_s = 2.0;   // window length
  int max_frames = 60;       // frames of the window used in the joint fit (evenly spread)
  double min_joint_range_deg = 15.0;
  bool keep_template_centres = false;
  void Check() const;
};

struct JointCalibration {
  std::string segment;
  double range_deg = 0.0;  // largest turn of the segment relative to its parent over the window
  bool functional = false; // centre found from the motion (false: kept from the scaled template)
  double length_mm = 0.0;  // distance from the parent's joint centre
};

struct SubjectCalibration {
  Skeleton skeleton;  // calibrated = true
  double scale = 1.0; // template scale from the subject's height
  int frames_used = 0;
  double rms_mm = 0.0, max_mm = 0.0;  // marker residuals over the frames used
  std::vector<JointCalibration> joints;
};

// markers: the trial in skeleton space (see skeleton_space.h), named like the template's markers.
SubjectCalibration CalibrateSubject(const Skeleton& skeleton_template, const MarkerTrajectories& markers,
                                    const SubjectCalibrationOptions& options);

// Frame f's markers in the skeleton's marker order (NaN where absent or not in the trial).
std::vector<int> MarkerColumns(const Skeleton& skeleton, const MarkerTrajectories& markers);
std::vector<Eigen::Vector3d> FrameObservations(const MarkerTrajectories& markers, const std::vector<int>& columns,
                                               size_t frame);

}  // namespace mocap
