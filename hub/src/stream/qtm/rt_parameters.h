// The XML answers to GetParameters (General, 3D, 6D) of the Qualisys RT protocol, built from
// what the hub knows: the trigger rate, the calibrated cameras, the labels and bodies seen so far.
//  - General: Frequency = serve's --rate; one Camera block per calibrated camera (ID, Model
//    "mocap-node", Serial = ID, Mode Marker, Position = camera centre in world mm and its
//    camera -> world rotation as Rot_r_c, Marker_Res in 1/64 px as QTM's subpixels, Marker_FOV).
//    Every element Qualisys' C++ SDK requires is present so strict parsers accept the block;
//    what the hub has no value for says so plainly (False, 0, None: no external time base, no
//    QTM processing actions but 3D tracking, exposures and thresholds not told).
//  - 3D: AxisUpwards is read from the cameras: the world axis closest to the mean of their
//    image-up directions (cameras are mounted upright), with its sign; then the labels.
//  - 6D: the bodies seen so far (names; Body() in the .cc says what else) and the Euler
//    convention of rt_frame.h.
// Pure code.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "bodies/body_definition.h"
#include "geometry/camera.h"
#include "stream/qtm/rt_frame.h"

namespace mocap::stream::qtm {

struct RtSystem {
  double rate_hz = 0.0;
  Rig rig;
  std::string axis_upwards = "+Z";
  std::vector<RigidBodyDefinition> bodies;  // serve --bodies: their markers go into the 6D XML
  std::vector<std::string> label_names;     // serve --labels: the 3D labels from the start
};

// "+X", "-Y", ... of a rig (see above); "+Z" for an empty rig.
std::string AxisUpwards(const Rig& rig);

// The whole document for protocol version 1.<minor>: <QTM_Parameters_Ver_1.minor> holding the
// blocks asked for (rt_command.h ParameterBlock bits).
std::string ParametersXml(const RtSystem& system, const RtNames& names, uint32_t blocks, int version_minor);

// Text escaped for XML character data.
std::string XmlEscape(const std::string& text);

}  // namespace mocap::stream::qtm
