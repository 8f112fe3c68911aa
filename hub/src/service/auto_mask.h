// Automatic masks for static reflections (what commercial systems call masking visible
// reflections): with the capture volume empty, every blob a camera keeps seeing at the same
// place is a reflection or a light, not a marker. From N frames of one camera this finds the
// blobs present in at least a fraction of the frames whose centroid stays put, masks each with a margin that grows with
// its size, and turns the mask into the node's representation: SetMask rectangles when few
// enough, else the node's 1-bit cell image in chunks (firmware/node/control.h limits). Masks
// are kept with the installation as JSON.
// Pure: no clock, no I/O. Error policy: too few or inconsistent frames and bad options throw
// std::invalid_argument; a mask file that does not parse throws std::runtime_error naming its
// source and the reason (the io layer's rule).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "geometry/camera.h"
#include "ingest/camera_frame.h"
#include "mocap.pb.h"

namespace mocap::service {

struct AutoMaskOptions {
  size_t min_frames = 10;
  double min_presence = 0.8;          // fraction of the frames a static blob appears in
  double match_radius_px = 3.0;       // a blob this close to a static blob's centre is that blob
  double steady_radius_px = 1.5;      // only sightings this close to a blob's mean centroid count
                                      // towards its presence: a marker creeping a few pixels while
                                      // the volume is not empty is no reflection
  double margin_px = 2.0;             // masked beyond each blob's own radius ...
  double margin_per_radius = 1.0;     // ... plus this many of its radii (halos grow with size)
  size_t max_candidates = 4096;       // blobs tracked across frames (bounded work on noisy input)

  // Empty when usable, otherwise why not.
  std::string Check() const;
};

struct StaticBlob {
  double x = 0.0, y = 0.0;   // mean centroid, px
  double radius_px = 0.0;    // of the largest sighting, from its area
  double presence = 0.0;     // fraction of the frames it was seen in
};

struct MaskRect {
  uint32_t x = 0, y = 0, width = 0, height = 0;  // pixels [x, x + width) x [y, y + height)
  bool operator==(const MaskRect& o) const {
    return x == o.x && y == o.y && width == o.width && height == o.height;
  }
};

struct CameraMask {
  uint32_t camera_id = 0;
  uint32_t width = 0, height = 0;
  size_t frames = 0;                // frames it was computed from
  std::vector<StaticBlob> blobs;    // what was found, for the operator
  std::vector<MaskRect> regions;    // masked pixels, inside the image, overlaps merged
};

// The mask of one camera from its frames (all of that camera, all of one image size).
CameraMask ComputeAutoMask(const std::vector<CameraFrame>& frames, const AutoMaskOptions& options);

// What the node accepts (firmware/node/control.h MN_CONTROL_MAX_RECTS, MN_CONTROL_MAX_MASK_CELLS,
// its 64 chunks; the wire's 896 bytes per chunk).
struct NodeMaskLimits {
  size_t max_rects = 16;
  uint64_t max_cells = 512u * 512u;
  uint32_t max_chunks = 64;
  size_t chunk_bytes = 896;
};

// The node's 1-bit cell image of a mask: bit (cy * cells_x + cx), least significant bit first,
// set when the cell touches a masked region. cell_px is the smallest that fits the node.
struct MaskBits {
  uint32_t cell_px = 0, cells_x = 0, cells_y = 0;
  std::vector<uint8_t> bits;
};
MaskBits RasteriseMask(const CameraMask& mask, const NodeMaskLimits& limits = {});

// The Control commands that install the mask on its node (node id and sequences are filled by
// ControlRequests::Submit): one clear for an empty mask, one SetMask of rectangles when they
// fit, else the cell image in chunks. Throws std::invalid_argument when no cell size fits.
std::vector<v1::Control> MaskCommands(const CameraMask& mask, const NodeMaskLimits& limits = {});

// The installation's mask file: {"version": 1, "cameras": [{camera_id, width, height, frames,
// blobs: [{x, y, radius_px, presence}], regions: [{x, y, width, height}]}]}.
// Cameras a mask actually masks: at least one region, and a camera of the calibration (every
// camera when the rig has none yet). What the operator is told ("masks N"); a mask that found
// nothing static, or one kept in the file for a camera no longer calibrated, masks nothing here.
size_t CountMaskedCameras(const std::vector<CameraMask>& masks, const Rig& rig);

nlohmann::json MasksToJson(const std::vector<CameraMask>& masks);
std::vector<CameraMask> MasksFromJson(const nlohmann::json& document, const std::string& source);

}  // namespace mocap::service
