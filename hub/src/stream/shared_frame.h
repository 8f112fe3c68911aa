// One published frame shared by every stream adapter: the hub's loop copies a LiveFrame once
// (without the tracker's samples, which only file writers need) and each adapter's thread
// reads the same immutable copy.
#pragma once

#include <memory>

#include "pipeline/live_frame.h"

namespace mocap::stream {

using SharedFrame = std::shared_ptr<const pipeline::LiveFrame>;

inline SharedFrame ShareFrame(const pipeline::LiveFrame& frame) {
  auto copy = std::make_shared<pipeline::LiveFrame>();
  copy->frame_number = frame.frame_number;
  copy->trigger_time_ns = frame.trigger_time_ns;
  copy->last_receive_ns = frame.last_receive_ns;
  copy->publish_ns = frame.publish_ns;
  copy->cameras = frame.cameras;
  copy->points = frame.points;
  copy->bodies = frame.bodies;
  copy->skeletons = frame.skeletons;
  copy->label_names = frame.label_names;
  return copy;
}

}  // namespace mocap::stream
