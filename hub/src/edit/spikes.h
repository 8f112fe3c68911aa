// Spike detection: samples whose acceleration (the second difference of three consecutive
// measured frames) is an outlier for that marker. The limit is robust to the motion's own
// accelerations: median + threshold x 1.4826 x MAD of the marker's accelerations (a floor of
// 0.01 mm/frame^2 keeps a marker at rest from calling noise a spike). A lone bad sample raises
// the acceleration of its neighbours too, at half the size: only the local peak is reported.
#pragma once

#include <cstdint>
#include <vector>

#include "edit/edited_take.h"

namespace mocap::edit {

struct Spike {
  size_t marker = 0;
  size_t frame_index = 0;
  double accel_mm_per_frame2 = 0.0;
  double limit_mm_per_frame2 = 0.0;
};

// Spikes of column `marker` within frame indices [first, last]. Markers with fewer than 8
// accelerations are not judged.
std::vector<Spike> FindSpikes(const EditedTake& take, size_t marker, size_t first, size_t last, double threshold);

}  // namespace mocap::edit
