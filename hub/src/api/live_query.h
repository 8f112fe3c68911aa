// The query of a /api/live WebSocket request, as a pure function: "max_fps=N" (1..1000) asks
// for at most N frames per second (a browser draws at 60 at most; the console asks for 60 and
// saves the rest of a 240 Hz rig's traffic); empty means every frame. Anything else is refused.
#pragma once

#include <optional>
#include <string>

namespace mocap::api {

struct LiveQuery {
  int max_fps = 0;  // 0: every frame
};

// nullopt when the query has an unknown parameter or a value out of range.
std::optional<LiveQuery> ParseLiveQuery(const std::string& query);

}  // namespace mocap::api
