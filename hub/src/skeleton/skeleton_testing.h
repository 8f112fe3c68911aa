// Shared by the skeleton layer's tests and benchmark: the 41-marker HDM05 / Vicon set, and the same
// with a toe-tip marker per foot (20 segments).
#pragma once

#include <string>
#include <vector>

#include "skeleton/skeleton_template.h"

namespace mocap {

inline std::vector<std::string> HdmMarkerNames() {
  return {"LFHD", "RFHD", "LBHD", "RBHD", "C7",   "T10",  "CLAV", "STRN", "RBAC", "LSHO", "LUPA", "LELB", "LFRM", "LWRA",
          "LWRB", "LFIN", "RSHO", "RUPA", "RELB", "RFRM", "RWRA", "RWRB", "RFIN", "LFWT", "RFWT", "LBWT", "RBWT", "LTHI",
          "LKNE", "LSHN", "LANK", "LHEE", "LTOE", "LMT5", "RTHI", "RKNE", "RSHN", "RANK", "RHEE", "RTOE", "RMT5"};
}

inline Skeleton TwentySegmentTemplate() {
  std::vector<std::string> names = HdmMarkerNames();
  names.push_back("LTOT");
  names.push_back("RTOT");
  std::vector<std::string> unplaced;
  return SkeletonTemplateFromNames(names, &unplaced);
}

}  // namespace mocap
