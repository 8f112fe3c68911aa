// For tests of the frame path (wire codec, session log, live ingest): a camera's frame of
// `blobs` blobs whose values follow from the camera and the frame number, so a test can make the
// same frame again to compare with what came back. The positions have sub-pixel parts (x in
// quarters, y in eighths of a pixel) that the wire's 1/256 px grid holds exactly.
#pragma once

#include <cstdint>

#include "ingest/camera_frame.h"

namespace mocap::testing {

inline CameraFrame FrameOfBlobs(uint32_t camera, uint64_t number, int blobs) {
  CameraFrame f;
  f.camera_id = camera;
  f.frame_number = number;
  f.width = 1280;
  f.height = 800;
  for (int i = 0; i < blobs; ++i) {
    Blob b;
    b.pixel = Eigen::Vector2d(10.0 + i * 4.25 + camera * 0.5, 20.0 + number * 0.125);
    b.area = 12 + i;
    b.peak = 250;
    b.mean = 180;
    f.blobs.push_back(b);
  }
  return f;
}

}  // namespace mocap::testing
