// Skeleton motion files: BVH (Biovision hierarchy), Acclaim ASF (skeleton) + AMC (motion), and an
// OpenSim .mot table of joint angles. All in skeleton space (+y up), millimetres and degrees.
// A frame without a solved pose repeats the last solved one (the first solved for leading
// frames): these formats have no gaps. Errors: std::runtime_error "<file>: <reason>".
//  BVH: every joint lists 3 rotation channels, its own degrees of freedom first in their order
//   (the rotation is their product in the listed order, as BVH readers take it), then the axes
//   it lacks (always 0); the root adds X/Y/Z position channels; leaves end in an End Site.
//  ASF/AMC: one bone per segment whose direction and length reach its only child (or its end);
//   a segment with several children (pelvis, chest) gets a zero-length bone and one fixed
//   connector bone per child ("<segment>_<child>", no dof). Units: length 1 (mm), angle deg.
//  .mot: time, the root's translation (tx, ty, tz in metres, OpenSim's unit) and every angle
//   named "<segment>_r<axis>", inDegrees=yes.
#pragma once

#include <string>
#include <vector>

#include "skeleton/skeleton.h"

namespace mocap {

struct SkeletonMotion {
  double rate_hz = 0.0;
  std::vector<std::vector<double>> poses;  // per frame: the pose vector (radians), or empty when unsolved
};

void WriteBvh(const Skeleton& skeleton, const SkeletonMotion& motion, const std::string& path);
void WriteAsf(const Skeleton& skeleton, const std::string& path);
void WriteAmc(const Skeleton& skeleton, const SkeletonMotion& motion, const std::string& path);
void WriteMot(const Skeleton& skeleton, const SkeletonMotion& motion, const std::string& path);

// The pose each frame is written with (see above); throws std::invalid_argument when no frame is solved.
std::vector<std::vector<double>> FilledPoses(const SkeletonMotion& motion);

}  // namespace mocap

namespace mocap {

// An OpenSim .mot / .sto table: the header up to "endheader", a line of column names, rows of
// numbers (tab or space separated). inDegrees=no converts angle columns ("*_r[xyz]") to degrees.
// Errors: std::runtime_error "<source>: line N: <reason>". Limits: 10000 columns, 10^7 cells.
struct MotTable {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  bool in_degrees = true;
};
MotTable ParseMot(const std::string& text, const std::string& source);
MotTable ReadMot(const std::string& path);
// Poses for `skeleton` from a table WriteMot wrote for it (columns by name; a missing one is an
// error); rate from the time column.
SkeletonMotion MotionFromMot(const Skeleton& skeleton, const MotTable& table, const std::string& source);

}  // namespace mocap
