// NatNet model definitions and frames of data from what the hub knows, in the layout of a
// bitstream version (3.0, 3.1, 4.0, 4.1). Units are metres (Motive's default: 1 unit = 1000 mm,
// the UnitsToMillimeters answer); axes are the hub's world axes.
//
// Model definitions (NAT_MODELDEF):
//  - one markerset per rigid body (its name; its markers "Marker1", "Marker2", ... as Motive
//    names a rigid body's markers), then, with a marker set (serve --labels), a markerset "all"
//    of its names;
//  - one rigid body per body of the bodies file: ID = its 1-based place in the file (LiveBody
//    id), parent -1, offset 0, its markers relative to its pivot (the reported position), active
//    labels 0, and (4.x) its markers' names;
//  - one skeleton per skeleton of serve --skeleton: its name (the subject), ID = the number of
//    rigid bodies + 1 + its place, and one rigid body description per bone (segment): the
//    segment's name, ID = its 1-based place, parent = its parent's (0 for the root, as Motive
//    does), offset = its joint centre in its parent's frame (m), no markers. No force plates,
//    devices, cameras or assets exist in the hub: none are described.
// Frames (NAT_FRAMEOFDATA):
//  - frame number: the hub's (low 32 bits);
//  - markerset data: each body's markers where its pose puts them, then the "all" set's names
//    where the frame has the named point (NaN where it has not);
//  - legacy "other markers": every point without a confirmed track (provisional or none);
//  - rigid bodies: ID, position, quaternion (x, y, z, w: body -> world), mean marker error (m),
//    params bit 0 = tracking valid (fitted in this frame; a pose predicted through an occlusion
//    is sent with the bit clear);
//  - labelled markers: every point. ID = the point's track id (LivePoint id, the same from the
//    track's first frame on, provisional or confirmed; past 2^31 - 1 it wraps to 1), 0 for a
//    point no track took; params 0x02 point-cloud solved, 0x08 has a name (marker set), 0x10
//    unlabelled (no confirmed track); size 0 and residual 0 (the hub measures reprojection error
//    in pixels, not the metres Motive reports here);
//  - skeletons: ID, bone count, then each bone as a rigid body: ID = skeleton ID << 16 | bone ID
//    (as Motive's), position and quaternion in the world frame (Motive's "global" skeleton
//    coordinates; segment -> world, the segment's frame being the skeleton's space at rest,
//    +y up), mean error = the fit's marker RMS (m), params bit 0 = tracking valid when the
//    frame was solved; a frame that could not be solved sends every bone with the bit clear and
//    NaN pose (never the last solved one);
//  - no assets, force plates or devices (counts 0);
//  - timecode 0; timestamp = frame number / rate (s since the session epoch, frame 0);
//  - the stamps on the hub's clock (CLOCK_REALTIME ns; ServerInfo's clock frequency is 1e9):
//    camera mid-exposure = the frame's trigger time (the cameras' trigger edge, as the own
//    stream's trigger_time_ns), data received = the last datagram of its frame set arrived,
//    transmit = when this packet was encoded (just before it is sent); 4.x precision timestamp
//    0 (no PTP time base);
//  - params 0 (neither recording nor models changed: the bodies are fixed for serve's life);
//    then the end-of-data tag (4 zero bytes).
// Points beyond what fits one datagram are left out (counted). Pure code: no I/O, no clock.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "bodies/body_definition.h"
#include "pipeline/live_frame.h"
#include "stream/natnet/natnet_packet.h"

namespace mocap::stream::natnet {

struct Model {
  double rate_hz = 0.0;
  std::vector<RigidBodyDefinition> bodies;   // serve --bodies, in the file's order
  std::vector<std::string> label_names;      // serve --labels
  // serve --skeleton: in the order of LiveFrame::skeletons. Skeleton k's ID is bodies + 1 + k.
  std::vector<std::shared_ptr<const pipeline::LiveSkeletonModel>> skeletons;
};

std::string EncodeModelDef(const Model& model, const Version& version);

struct FrameStamps {
  uint64_t transmit_ns = 0;
};

// points_dropped (optional) counts the points left out to fit kMaxPacket.
std::string EncodeFrame(const pipeline::LiveFrame& frame, const Model& model, const Version& version,
                        const FrameStamps& stamps, uint64_t* points_dropped = nullptr);

}  // namespace mocap::stream::natnet
