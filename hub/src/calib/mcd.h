// Seed 000's .mcd recordings: "CameraCount: N", N Tsai camera blocks (19 lines each, blocks
// separated by a blank line), then frames: "Frame: K" followed by one "marksCount: M x = X y = Y
// ..." line per camera in camera order. Read into the hub's types so that such recordings can be
// converted to session directories and reconstructed like any other.
#pragma once

#include <string>
#include <vector>

#include "calib/tsai.h"
#include "ingest/camera_frame.h"

namespace mocap {

struct McdRecording {
  std::vector<TsaiCamera> cameras;  // camera ids are 1..N in this order
  std::vector<FrameSet> frames;     // every camera present in every frame, blobs as recorded
};

// Throws std::runtime_error naming file and line for anything malformed: a wrong camera count,
// a short Tsai block, a frame with the wrong number of camera lines, a marks line whose count
// disagrees with its coordinates.
McdRecording ReadMcd(const std::string& path);
McdRecording ParseMcd(const std::string& text, const std::string& source);

}  // namespace mocap
