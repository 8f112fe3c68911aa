// Shared simulated-fault options (see fault_options.h).
#include "cli/fault_options.h"

namespace mocap {

void AddCameraFaultOptions(CLI::App* command, ProjectOptions* p) {
  command->add_option("--noise-px", p->noise_px, "Centroid noise sigma, px")->capture_default_str();
  command->add_option("--occlusion", p->occlusion, "Probability a marker is hidden from one camera at a frame")
      ->capture_default_str();
  command->add_option("--occlusion-frames", p->occlusion_frames, "Mean length of an occlusion, frames")
      ->capture_default_str();
  command->add_option("--spurious", p->spurious, "False blobs per camera per frame (half static, half flicker)")
      ->capture_default_str();
  command->add_option("--drop-frames", p->drop_frames, "Probability a camera's whole frame is lost")
      ->capture_default_str();
  command->add_option("--marker-mm", p->marker_diameter_mm, "Marker diameter (sets blob size), mm")
      ->capture_default_str();
}

}  // namespace mocap
