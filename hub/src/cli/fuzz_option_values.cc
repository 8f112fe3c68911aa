// libFuzzer entry for the option values the hub parses itself (from the command line or a config
// file): --bump CAM:DEG:MM, --lframe points, HOST:PORT addresses, stream parts, log levels. Any
// text must parse or throw invalid_argument (UsageError is one); what parses must be within the
// documented ranges, and an address written back as HOST:PORT must parse to itself.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "cli/calibrate_helpers.h"
#include "ingest/udp_socket.h"
#include "simcore/camera_bump.h"
#include "stream/stream_encoding.h"
#include "util/log.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const mocap::CameraBump bump = mocap::ParseCameraBump(text);
    if (bump.camera_id < 1 || !(std::abs(bump.degrees) <= 180.0) || !(std::abs(bump.mm) <= 1e5)) __builtin_trap();
  } catch (const std::invalid_argument&) {
  }
  try {
    for (const Eigen::Vector3d& p : mocap::ParsePointList(text, "--lframe"))
      if (!p.allFinite()) __builtin_trap();
  } catch (const std::invalid_argument&) {
  }
  try {
    const mocap::HostPort address = mocap::ParseHostPort(text);
    const std::string written = (address.host.empty() ? "*" : address.host) + ":" + std::to_string(address.port);
    const mocap::HostPort again = mocap::ParseHostPort(written);
    if (again.host != address.host || again.port != address.port) __builtin_trap();
    // The port is the whole text after the last colon: nothing past a NUL was skipped.
    if (text.find('\0', text.rfind(':')) != std::string::npos) __builtin_trap();
  } catch (const std::invalid_argument&) {
  }
  try {
    if (mocap::stream::ParseParts(text) & ~mocap::stream::kAllParts) __builtin_trap();
  } catch (const std::invalid_argument&) {
  }
  (void)mocap::log::ParseLevel(text);
  return 0;
}
