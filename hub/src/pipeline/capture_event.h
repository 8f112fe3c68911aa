// A capture of the live hub starting or ending, for whatever reason (asked through the API, a
// live wanding's, a full disk, the service stopping), as the hub's loop tells its listeners
// (service/live_subscribers.h); stream adapters whose protocol reports captures react to it
// (stream/stream_sink.h).
#pragma once

#include <string>

namespace mocap::pipeline {

struct CaptureEvent {
  enum class Kind { kStarted, kStopped };
  Kind kind = Kind::kStarted;
  std::string session;  // the session's name (the sessions directory's entry)
};

}  // namespace mocap::pipeline
