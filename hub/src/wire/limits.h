// Shared wire rules of protocol v1 (the firmware's firmware/wire/wire.h states the same numbers).
// Both sides enforce them on encode and decode so that any datagram one side accepts the other does.
#pragma once

#include <cstddef>
#include <cstdint>

namespace mocap::wire {

constexpr uint32_t kProtocolVersion = 1;
constexpr size_t kMaxDatagramBytes = 1400;
// One Packet: the datagram less the authenticated envelope (wire/envelope.h), also when a
// development rig sends it plain (firmware: MN_WIRE_MAX_PACKET).
constexpr size_t kMaxPacketBytes = 1352;
// 48 markers of at most 24 encoded bytes each plus the frame header: at most 1231 bytes, within
// the packet budget.
constexpr uint32_t kMarkersPerChunk = 48;
constexpr uint32_t kMaxMarkersPerFrame = 1024;
constexpr uint32_t kMaxChunksPerFrame = (kMaxMarkersPerFrame + kMarkersPerChunk - 1) / kMarkersPerChunk;
// Image sides below 8192 px keep every 1/256 px coordinate inside a 3-byte varint.
constexpr uint32_t kMaxImageSide = 8191;
constexpr uint32_t kMaxBlobArea = (1u << 21) - 1;
constexpr uint32_t kMaxBrightness = 65535;
constexpr uint32_t kMarkerFlagsMask = 7;
constexpr uint32_t kFrameFlagsMask = 3;
constexpr uint32_t kMaxMaskRects = 16;
constexpr size_t kMaxMaskBitsBytes = 896;
constexpr size_t kMaxPreviewChunkBytes = 1200;
constexpr size_t kMaxFirmwareVersionChars = 32;
// ControlAck.reason: nanopb's 96-byte field less its terminating NUL.
constexpr size_t kMaxAckReasonBytes = 95;
// Centroids travel as 1/256 px fixed point.
constexpr double kSubpixelScale = 256.0;

}  // namespace mocap::wire
