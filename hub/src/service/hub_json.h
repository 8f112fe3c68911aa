// The live hub's JSON views of what its loop holds, as the API answers them: pure functions (the
// caller passes the time and holds whatever lock guards their arguments).
#pragma once

#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

#include "geometry/camera.h"
#include "ingest/ingest_stats.h"
#include "service/auto_mask.h"
#include "service/control_requests.h"
#include "service/node_registry.h"
#include "service/waiters.h"

namespace mocap::service {

// One finished control request: node, outcome, reason, datagrams, retransmissions, ms.
nlohmann::json RequestJson(const RequestResult& result);

// One node of the registry with its reception figures from `stats` (zeros for a node outside
// the calibration), whether `masks` mask it, and how long ago it was last seen at now_ns.
nlohmann::json NodeJson(const NodeEntry& node, const IngestStats& stats, const std::vector<CameraMask>& masks,
                        uint64_t now_ns);

// The cameras of /api/calibration: intrinsics, rotation, translation and centre in the world.
nlohmann::json CamerasJson(const Rig& rig);

// /api/blobs: per camera of the rig, whether the snapshot's frame set has it, its blobs
// (x, y, area) and its mask's rectangles; "frame" is null when no frame set came in time.
nlohmann::json BlobsJson(const Rig& rig, const BlobsSnapshot& snapshot);

}  // namespace mocap::service
