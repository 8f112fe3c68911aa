// Benchmark: wand calibration of a synthetic 12-camera rig from 3000 frames on one thread.
// Prints the stage timings and the accuracy figures; the target is under 30 s in total.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>

#include <Eigen/Geometry>

#include "geometry/rigid_fit.h"
#include "simcore/test_scenes.h"
#include "calib/wand_calibration.h"

int main(int argc, char** argv) {
  using namespace mocap;
  const int cameras = argc > 1 ? std::atoi(argv[1]) : 12;
  const int frames = argc > 2 ? std::atoi(argv[2]) : 3000;
  const double noise = argc > 3 ? std::atof(argv[3]) : 0.15;
  const Rig truth = testing::RingRig(cameras, 7);
  const WandGeometry wand = WandGeometry::TwoMarker(500.0);
  const testing::WandScene scene = testing::MakeWandScene(truth, wand.marker_offsets_mm, frames, noise, 8);
  WandCalibrationOptions options;
  options.bundle.num_threads = 1;
  const auto start = std::chrono::steady_clock::now();
  const WandCalibrationResult result = CalibrateWand(scene.frames, truth, wand, options);
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  std::vector<Eigen::Vector3d> source, target;
  for (const Camera& camera : result.rig.cameras) {
    source.push_back(camera.CenterInWorld());
    target.push_back(truth.Find(camera.id)->CenterInWorld());
  }
  const SimilarityTransform rigid = FitRigid(source, target);
  double centre = 0.0, rotation = 0.0;
  for (const Camera& camera : result.rig.cameras) {
    const Camera& expected = *truth.Find(camera.id);
    centre = std::max(centre, (rigid.Apply(camera.CenterInWorld()) - expected.CenterInWorld()).norm());
    const Eigen::Matrix3d aligned = camera.rotation * rigid.rotation.transpose();
    rotation = std::max(rotation, Eigen::AngleAxisd(aligned * expected.rotation.transpose()).angle() * 180.0 / M_PI);
  }
  std::printf("cameras %d frames %d noise %.3f px (one thread), process CPU %.2f s\n", cameras, frames, noise,
              static_cast<double>(std::clock()) / CLOCKS_PER_SEC);
  std::printf("time: select %.2f s, initialise %.2f s, bundle %.2f s, total %.2f s (%d solver iterations)\n",
              result.select_seconds, result.initialize_seconds, result.bundle_seconds, total,
              result.solver_iterations);
  std::printf("accepted %zu/%d cameras, frames used %zu/%zu\n", result.rig.cameras.size(), cameras,
              result.frames_used, result.frames_selected);
  std::printf("max centre error %.3f mm, max rotation error %.4f deg, scale %.6f\n", centre, rotation,
              FitSimilarity(source, target).scale);
  std::printf("reprojection RMS %.3f px (2-D error length per observation); wand length error mean %.3f mm rms %.3f mm p95 %.3f mm "
              "max %.3f mm\n",
              result.reprojection_rms_px, result.wand_length.mean_mm, result.wand_length.rms_mm,
              result.wand_length.p95_abs_mm, result.wand_length.max_abs_mm);
  return 0;
}
