// Conversion between the hub's CameraFrame and protocol-v1 marker frames / datagrams.
#pragma once

#include <cstdint>
#include <vector>

#include "ingest/camera_frame.h"
#include "mocap.pb.h"

namespace mocap {

// Whole-frame message (all markers, single chunk). The camera id travels as node id.
v1::MarkerFrame ToMarkerFrame(const CameraFrame& frame);
CameraFrame FromMarkerFrame(const v1::MarkerFrame& frame, uint64_t receive_time_ns);

// The datagrams a node would send for this frame (chunked, each <= 1400 bytes).
std::vector<std::vector<uint8_t>> EncodeCameraFrame(const CameraFrame& frame);

}  // namespace mocap
