// The /api/live query (see live_query.h).
#include "api/live_query.h"

namespace mocap::api {

std::optional<LiveQuery> ParseLiveQuery(const std::string& query) {
  LiveQuery parsed;
  size_t start = 0;
  while (start < query.size()) {
    size_t end = query.find('&', start);
    if (end == std::string::npos) end = query.size();
    const std::string pair = query.substr(start, end - start);
    start = end + 1;
    if (pair.empty()) continue;
    const size_t eq = pair.find('=');
    if (eq == std::string::npos || pair.substr(0, eq) != "max_fps") return std::nullopt;
    const std::string value = pair.substr(eq + 1);
    if (value.empty() || value.size() > 4) return std::nullopt;
    int n = 0;
    for (char c : value) {
      if (c < '0' || c > '9') return std::nullopt;
      n = n * 10 + (c - '0');
    }
    if (n < 1 || n > 1000) return std::nullopt;
    parsed.max_fps = n;
  }
  return parsed;
}

}  // namespace mocap::api
