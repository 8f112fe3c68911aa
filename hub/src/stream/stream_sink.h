// What every stream adapter is to the hub: it takes each published frame (queued for its own
// thread, never blocking the hub's loop), reports its figures for /api/status, and hears the
// hub's captures start and stop (pipeline/capture_event.h), which only protocols that report
// captures act on (the Qualisys RT server's Capture Started / Stopped). Called on the hub's loop
// thread: each must return at once.
#pragma once

#include <nlohmann/json_fwd.hpp>

#include "pipeline/capture_event.h"
#include "stream/shared_frame.h"

namespace mocap::stream {

class StreamSink {
 public:
  virtual ~StreamSink() = default;
  virtual void Publish(SharedFrame frame) = 0;
  virtual nlohmann::json StatsJson() const = 0;
  virtual void OnCapture(const pipeline::CaptureEvent& event) { (void)event; }
};

}  // namespace mocap::stream
