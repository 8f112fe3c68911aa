// libFuzzer target: arbitrary request paths through the console's static file lookup (over the
// real hub/web directory and a mount of it at /vendor/x/) and arbitrary /api/live queries. A
// path served must name a file inside its mount; nothing may crash or throw.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "api/live_query.h"
#include "api/static_files.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  static const std::vector<mocap::api::StaticMount> mounts = {{"/", MOCAP_WEB_SOURCE_DIR},
                                                              {"/vendor/x/", MOCAP_WEB_SOURCE_DIR "/js"}};
  const mocap::api::StaticFile file = mocap::api::ResolveStaticFile(mounts, input);
  if (file.status == 200) {
    const std::string root = MOCAP_WEB_SOURCE_DIR;
    if (file.path.compare(0, root.size(), root) != 0 || file.content_type.empty()) std::abort();
  } else if (file.status != 404 || file.reason.empty()) {
    std::abort();
  }
  const auto query = mocap::api::ParseLiveQuery(input);
  if (query && (query->max_fps < 0 || query->max_fps > 1000)) std::abort();
  return 0;
}
