// The reconstruction and tracking options `reconstruct` and `serve` share (see commands.h):
// what remains to set once the gates follow the rig's centroid noise (recon/rig_noise.h).
#include <memory>

#include "cli/commands.h"

namespace mocap {

void AddRigOptions(CLI::App& command, ReconstructorOptions* recon, TrackerOptions* tracker) {
  command
      .add_option("--centroid-noise-px", recon->centroid_noise_px,
                  "Centroid noise sigma per image axis (px) the gates follow; 0: the calibration's "
                  "centroid_rms_px, then measured from the residuals")
      ->check(FiniteRange(0.0, 50.0))
      ->capture_default_str();
  command
      .add_option_function<int>(
          "--min-views",
          [recon, tracker](const int& views) {
            recon->min_views_without_prediction = views;
            tracker->birth_min_views = views;
          },
          "Views a marker no track predicted needs (and a new track's points): 2 takes two-view candidates "
          "that persist and move like a marker (default), 3 only markers seen by three cameras")
      ->check(CLI::Range(2, 64))
      ->default_str("2");
  command
      .add_option("--two-view-birth-frames", tracker->two_view_birth_frames,
                  "Frames in a row a track begun on two-view points must be measured before it is output")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  command
      .add_option("--kalman-acceleration-noise", tracker->kalman.acceleration_noise,
                  "Tracker's process noise: white-noise acceleration, mm/s^2 (one sigma)")
      ->check(FiniteRange(1.0, 1e7))
      ->capture_default_str();
  command
      .add_option("--rigid-max-deviation-mm", tracker->rigid.max_deviation_mm,
                  "Rigid-pair model: a link breaks when a distance strays this far from its mean (mm)")
      ->check(FiniteRange(0.1, 1000.0))
      ->capture_default_str();
  command
      .add_option("--rigid-max-std-mm", tracker->rigid.max_std_mm,
                  "Rigid-pair model: a link breaks when its distances' standard deviation grows past this (mm)")
      ->check(FiniteRange(0.1, 1000.0))
      ->capture_default_str();
}

}  // namespace mocap
