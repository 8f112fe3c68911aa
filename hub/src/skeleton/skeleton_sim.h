// A simulated subject: a skeleton (a template made into one person: scaled, each bone and joint
// offset and each marker moved by a seeded random amount) animated with known joint angles, its
// markers carried by their segments plus soft-tissue wobble (each marker swinging about its place
// on the segment), so that truth angles and lengths exist for `skeleton eval`.
// Motions (procedural): range of motion: from the rest pose (all angles zero at t = 0, the
// calibration's reference) every degree of freedom swings over a good part of its range at its
// own frequency (0.5-1.3 Hz, so each turns within 2 s), the middle rotation of 3-dof joints kept
// within 45 deg (away from gimbal lock); gait: walking at 1.2 m/s, one stride per second, legs
// and arms swinging in opposition, the pelvis bobbing and turning with the stride.
#pragma once

#include <cstdint>
#include <string>

#include "io/marker_trajectories.h"
#include "skeleton/motion_files.h"
#include "skeleton/skeleton.h"

namespace mocap {

enum class SkeletonSimMotion { kRangeOfMotion, kGait };
std::string SkeletonSimMotionName(SkeletonSimMotion motion);
SkeletonSimMotion SkeletonSimMotionFromName(const std::string& name);  // throws std::invalid_argument

struct SkeletonSimOptions {
  SkeletonSimMotion motion = SkeletonSimMotion::kRangeOfMotion;
  double rate_hz = 60.0;
  double duration_s = 4.0;
  double scale = 1.0;           // the subject's size against the template's 1.75 m
  double variation = 0.06;      // each offset scaled by up to 1 +- this (seeded)
  double marker_shift_mm = 10.0;// each marker moved up to this on its segment (seeded)
  double wobble_mm = 2.0;       // soft-tissue swing amplitude
  uint64_t seed = 1;
  void Check() const;
};

struct SkeletonSimulation {
  Skeleton subject;               // the true skeleton (calibrated = true)
  SkeletonMotion motion;          // true poses, every frame
  MarkerTrajectories markers;     // skeleton space, with wobble
};

SkeletonSimulation SimulateSkeleton(const Skeleton& skeleton_template, const SkeletonSimOptions& options);

}  // namespace mocap
