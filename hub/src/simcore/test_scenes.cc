// Test scenes on the simulator's parts (see test_scenes.h).
#include "simcore/test_scenes.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <Eigen/Geometry>

#include "io/trc.h"
#include "simcore/look_at.h"
#include "simcore/synthetic_motion.h"

namespace mocap::testing {
namespace {

constexpr double kPi = 3.14159265358979323846;

CameraIntrinsics Pinhole(double fx, int width, int height) {
  CameraIntrinsics in;
  in.width = width;
  in.height = height;
  in.fx = fx;
  in.fy = fx;
  in.cx = 0.5 * width;
  in.cy = 0.5 * height;
  return in;
}

// The tests' occlusion is a start chance per frame and a mean length; the projector's is the
// stationary share of hidden frames of the same two-state chain.
double StationaryOcclusion(double start, int frames) {
  const double hidden = start * std::max(1, frames);
  return hidden / (1.0 + hidden);
}

}  // namespace

Rig MakeRingRig(int num_cameras, double radius_mm, double height_mm, const Eigen::Vector3d& target, double fx,
                int width, int height, const std::array<double, 5>& distortion) {
  Rig rig;
  for (int i = 0; i < num_cameras; ++i) {
    const double angle = 2.0 * kPi * i / num_cameras;
    // Alternate heights a little so that no two cameras share an epipolar plane family.
    const double z = height_mm + ((i % 2 == 0) ? 0.0 : -0.35 * height_mm);
    Camera camera;
    camera.id = static_cast<uint32_t>(i + 1);
    camera.intrinsics = Pinhole(fx, width, height);
    camera.intrinsics.distortion = distortion;
    AimCamera(Eigen::Vector3d(radius_mm * std::cos(angle), radius_mm * std::sin(angle), z), target,
              Eigen::Vector3d::UnitZ(), &camera);
    rig.cameras.push_back(camera);
  }
  return rig;
}

Camera LookAtCamera(uint32_t id, const Eigen::Vector3d& centre_in_world, const Eigen::Vector3d& target_in_world) {
  Camera camera;
  camera.id = id;
  camera.intrinsics = Pinhole(900.0, 1280, 800);
  AimCamera(centre_in_world, target_in_world, Eigen::Vector3d::UnitZ(), &camera);
  return camera;
}

Rig RingRig(int n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-1.0, 1.0);
  Rig rig;
  for (int i = 0; i < n; ++i) {
    const double angle = 2.0 * kPi * i / n + 0.1 * jitter(rng);
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

SyntheticMotion::SyntheticMotion(int num_markers, int markers_per_body, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const int num_bodies = (num_markers + markers_per_body - 1) / markers_per_body;
  for (int b = 0; b < num_bodies; ++b) {
    Body body;
    body.center = Eigen::Vector3d(350.0 * unit(rng), 350.0 * unit(rng), 900.0 + 300.0 * unit(rng));
    body.amplitude = Eigen::Vector3d(250.0 + 100.0 * unit(rng), 250.0 + 100.0 * unit(rng), 150.0 + 50.0 * unit(rng));
    body.frequency = Eigen::Vector3d(0.4 + 0.2 * unit(rng), 0.5 + 0.2 * unit(rng), 0.7 + 0.2 * unit(rng));
    body.phase = Eigen::Vector3d(3.0 * unit(rng), 3.0 * unit(rng), 3.0 * unit(rng));
    body.spin_rate = 1.5 * unit(rng);
    body.tilt = 0.5 * unit(rng);
    bodies_.push_back(body);
  }
  for (int m = 0; m < num_markers; ++m) {
    body_of_marker_.push_back(m / markers_per_body);
    // Markers 60-150 mm from the body centre, like markers on a limb segment.
    Eigen::Vector3d offset(unit(rng), unit(rng), unit(rng));
    offset = offset.normalized() * (60.0 + 90.0 * std::abs(unit(rng)));
    offsets_.push_back(offset);
  }
}

std::vector<Eigen::Vector3d> SyntheticMotion::At(double time_s) const {
  std::vector<Eigen::Vector3d> markers(offsets_.size());
  for (size_t m = 0; m < offsets_.size(); ++m) {
    const Body& body = bodies_[body_of_marker_[m]];
    Eigen::Vector3d position = body.center;
    for (int axis = 0; axis < 3; ++axis)
      position[axis] += body.amplitude[axis] * std::sin(2.0 * kPi * body.frequency[axis] * time_s + body.phase[axis]);
    const Eigen::Matrix3d rotation = (Eigen::AngleAxisd(body.spin_rate * time_s, Eigen::Vector3d::UnitZ()) *
                                      Eigen::AngleAxisd(body.tilt, Eigen::Vector3d::UnitX()))
                                         .toRotationMatrix();
    markers[m] = position + rotation * offsets_[m];
  }
  return markers;
}

FrameProjector::FrameProjector(const Rig& rig, const ProjectionFaults& faults, uint32_t seed) : rig_(rig) {
  options_.noise_px = faults.noise_px;
  options_.occlusion = StationaryOcclusion(faults.occlusion, faults.occlusion_frames);
  options_.occlusion_frames = std::max(1, faults.occlusion_frames);
  options_.spurious = faults.spurious;
  options_.drop_frames = faults.drop_frames;
  options_.merge_px = 0.0;
  options_.seed = seed;
}

void FrameProjector::Project(uint64_t frame_number, const std::vector<Eigen::Vector3d>& markers, FrameSet* frame_set,
                             BlobTruth* truth) {
  if (!projector_) projector_ = std::make_unique<FaultyProjector>(rig_, markers.size(), options_);
  std::vector<CameraFrame> frames =
      projector_->Project(frame_number, 0, markers.data(), &seeing_, &blob_markers_);
  frame_set->frame_number = frame_number;
  frame_set->cameras.clear();
  truth->assign(rig_.cameras.size(), {});
  size_t next = 0;
  for (size_t c = 0; c < rig_.cameras.size() && next < frames.size(); ++c) {
    if (frames[next].camera_id != rig_.cameras[c].id) continue;  // dropped
    (*truth)[c] = blob_markers_[next];
    frame_set->cameras.push_back(std::move(frames[next]));
    ++next;
  }
}

WandScene MakeWandScene(const Rig& rig, const std::vector<double>& marker_offsets_mm, int frames, double noise_px,
                        uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  ProjectOptions options;
  options.noise_px = noise_px;
  options.merge_px = 0.0;
  options.seed = seed;
  FaultyProjector projector(rig, marker_offsets_mm.size(), options);
  std::vector<int> seeing;
  std::vector<Eigen::Vector3d> points(marker_offsets_mm.size());
  WandScene scene;
  for (int f = 0; f < frames; ++f) {
    const Eigen::Vector3d centre(1500.0 * unit(rng), 1500.0 * unit(rng), 1100.0 + 900.0 * unit(rng));
    Eigen::Vector3d axis(unit(rng), unit(rng), unit(rng));
    if (axis.norm() < 0.1) axis = Eigen::Vector3d::UnitX();
    axis.normalize();
    for (size_t k = 0; k < points.size(); ++k) points[k] = centre + marker_offsets_mm[k] * axis;
    FrameSet set;
    set.frame_number = static_cast<uint64_t>(f);
    set.cameras = projector.Project(set.frame_number, 0, points.data(), &seeing);
    for (CameraFrame& frame : set.cameras) std::shuffle(frame.blobs.begin(), frame.blobs.end(), rng);
    scene.frames.push_back(std::move(set));
    scene.wand_centres.push_back(centre);
  }
  return scene;
}

MarkerTrajectories WalkOrSyntheticWalker(const std::string& shared_dir) {
  const std::string walk = shared_dir + "/data/motions/walk.trc";
  if (std::filesystem::exists(walk)) return ReadTrc(walk);
  SyntheticMotionOptions options;
  options.markers = 41;
  options.frames = 151;
  options.rate_hz = 60.0;
  return MakeSyntheticMotion(options);
}

}  // namespace mocap::testing
