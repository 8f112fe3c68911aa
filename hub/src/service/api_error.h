// A request the live hub cannot honour, with the HTTP status that says whose fault it was:
// 400 a bad value, 404 no such node or session, 409 a conflicting state (a capture already
// running), 422 data that does not show what was asked (no L-frame in view), 504 a node that did
// not answer in time, 500 our own failure.
#pragma once

#include <stdexcept>
#include <string>

namespace mocap::service {

struct ApiError : std::runtime_error {
  ApiError(int status, const std::string& message) : std::runtime_error(message), status(status) {}
  int status;
};

}  // namespace mocap::service
