// Skeleton templates built by rules from a marker set's names: a humanoid segment tree (pelvis,
// legs, trunk, head, arms) whose segments are kept only where the set puts markers on them, each
// marker placed on its segment at a rough offset for a 1.75 m person (calibration replaces them).
// Rules know the 41-marker Vicon / HDM05 set (LFWT, LKNE, C7, ...) and the OpenSim gait sets
// (R.ASIS, L.Thigh.Upper, Sternum, ...); sides come from an L/R prefix ("L", "L.", "R", "R.").
// A segment without markers is left out and its children join its parent; a trunk with markers
// only on one of its two parts (Spine: T10, STRN; Chest: C7, CLAV, back) is one segment.
#pragma once

#include <string>
#include <vector>

#include "skeleton/skeleton.h"

namespace mocap {

// Names the rules do not place are listed in *unplaced (not an error: extra markers, e.g. a
// technical cluster, are left out). Throws std::invalid_argument when no pelvis marker is known
// or fewer than 2 segments would remain.
Skeleton SkeletonTemplateFromNames(const std::vector<std::string>& names, std::vector<std::string>* unplaced);

}  // namespace mocap
