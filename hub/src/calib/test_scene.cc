// Synthetic calibration scenes for tests (see test_scene.h).
#include "calib/test_scene.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <Eigen/Geometry>

namespace mocap::testing {

Camera LookAtCamera(uint32_t id, const Eigen::Vector3d& centre_in_world, const Eigen::Vector3d& target_in_world) {
  Camera camera;
  camera.id = id;
  const Eigen::Vector3d forward = (target_in_world - centre_in_world).normalized();
  const Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d down = forward.cross(right);
  camera.rotation.row(0) = right;
  camera.rotation.row(1) = down;
  camera.rotation.row(2) = forward;
  camera.translation = -camera.rotation * centre_in_world;
  camera.intrinsics.width = 1280;
  camera.intrinsics.height = 800;
  camera.intrinsics.fx = 900.0;
  camera.intrinsics.fy = 900.0;
  camera.intrinsics.cx = 640.0;
  camera.intrinsics.cy = 400.0;
  return camera;
}

Rig RingRig(int n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-1.0, 1.0);
  Rig rig;
  for (int i = 0; i < n; ++i) {
    const double angle = 2.0 * M_PI * i / n + 0.1 * jitter(rng);
    const Eigen::Vector3d centre(4000.0 * std::cos(angle), 4000.0 * std::sin(angle), i % 2 == 0 ? 2200.0 : 2800.0);
    const Eigen::Vector3d target(200.0 * jitter(rng), 200.0 * jitter(rng), 1000.0 + 100.0 * jitter(rng));
    Camera camera = LookAtCamera(static_cast<uint32_t>(i + 1), centre, target);
    camera.intrinsics.fx += 20.0 * jitter(rng);
    camera.intrinsics.fy = camera.intrinsics.fx * (1.0 + 0.002 * jitter(rng));
    camera.intrinsics.cx += 8.0 * jitter(rng);
    camera.intrinsics.cy += 8.0 * jitter(rng);
    camera.intrinsics.distortion = {-0.22 + 0.03 * jitter(rng), 0.07, 0.0008 * jitter(rng), 0.0008 * jitter(rng),
                                    -0.01};
    rig.cameras.push_back(camera);
  }
  return rig;
}

WandScene MakeWandScene(const Rig& rig, const WandGeometry& wand, int frames, double noise_px, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::normal_distribution<double> noise(0.0, noise_px);
  WandScene scene;
  for (int f = 0; f < frames; ++f) {
    const Eigen::Vector3d centre(1500.0 * unit(rng), 1500.0 * unit(rng), 1100.0 + 900.0 * unit(rng));
    Eigen::Vector3d axis(unit(rng), unit(rng), unit(rng));
    if (axis.norm() < 0.1) axis = Eigen::Vector3d::UnitX();
    axis.normalize();
    FrameSet set;
    set.frame_number = static_cast<uint64_t>(f);
    for (const Camera& camera : rig.cameras) {
      CameraFrame frame;
      frame.camera_id = camera.id;
      frame.frame_number = set.frame_number;
      frame.width = static_cast<uint32_t>(camera.intrinsics.width);
      frame.height = static_cast<uint32_t>(camera.intrinsics.height);
      for (double offset : wand.marker_offsets_mm) {
        Eigen::Vector2d pixel;
        if (!camera.ProjectToPixel(centre + offset * axis, &pixel) || !camera.InImage(pixel)) continue;
        // Far outside the field of view the lens polynomial folds back into the image; a real
        // lens never shows such points, so only pixels that undistort to their own ray count.
        const Eigen::Vector3d in_cam = camera.PointInCamera(centre + offset * axis);
        if ((camera.UndistortPixel(pixel) - in_cam.head<2>() / in_cam.z()).norm() > 1e-6) continue;
        Blob blob;
        blob.pixel = pixel + Eigen::Vector2d(noise(rng), noise(rng));
        frame.blobs.push_back(blob);
      }
      std::shuffle(frame.blobs.begin(), frame.blobs.end(), rng);
      set.cameras.push_back(frame);
    }
    scene.frames.push_back(set);
    scene.wand_centres.push_back(centre);
  }
  return scene;
}

}  // namespace mocap::testing
