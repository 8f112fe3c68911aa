// Helpers of the shared trajectory type.
#include "io/marker_trajectories.h"

#include <cstdio>

namespace mocap {

std::string DefaultMarkerName(size_t index) {
  char name[32];
  std::snprintf(name, sizeof(name), "M%03zu", index + 1);
  return name;
}

}  // namespace mocap
