// Synthetic rig, motion and blob projection for tests and the bench.
#include "recon/testing/synthetic_scene.h"

#include <cmath>

#include <Eigen/Geometry>

namespace mocap::testing {

Rig MakeRingRig(int num_cameras, double radius_mm, double height_mm, const Eigen::Vector3d& target,
                double fx, int width, int height, const std::array<double, 5>& distortion) {
  Rig rig;
  for (int i = 0; i < num_cameras; ++i) {
    const double angle = 2.0 * M_PI * i / num_cameras;
    // Alternate heights a little so that no two cameras share an epipolar plane family.
    const double z = height_mm + ((i % 2 == 0) ? 0.0 : -0.35 * height_mm);
    const Eigen::Vector3d center(radius_mm * std::cos(angle), radius_mm * std::sin(angle), z);
    const Eigen::Vector3d forward = (target - center).normalized();
    const Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitZ()).normalized();
    const Eigen::Vector3d down = forward.cross(right);
    Camera camera;
    camera.id = static_cast<uint32_t>(i + 1);
    camera.intrinsics.width = width;
    camera.intrinsics.height = height;
    camera.intrinsics.fx = fx;
    camera.intrinsics.fy = fx;
    camera.intrinsics.cx = 0.5 * width;
    camera.intrinsics.cy = 0.5 * height;
    camera.intrinsics.distortion = distortion;
    camera.rotation.row(0) = right.transpose();
    camera.rotation.row(1) = down.transpose();
    camera.rotation.row(2) = forward.transpose();
    camera.translation = -camera.rotation * center;
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
    body.amplitude = Eigen::Vector3d(250.0 + 100.0 * unit(rng), 250.0 + 100.0 * unit(rng),
                                     150.0 + 50.0 * unit(rng));
    body.frequency = Eigen::Vector3d(0.4 + 0.2 * unit(rng), 0.5 + 0.2 * unit(rng),
                                     0.7 + 0.2 * unit(rng));
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
    for (int axis = 0; axis < 3; ++axis) {
      position[axis] += body.amplitude[axis] *
                        std::sin(2.0 * M_PI * body.frequency[axis] * time_s + body.phase[axis]);
    }
    const Eigen::Matrix3d rotation =
        (Eigen::AngleAxisd(body.spin_rate * time_s, Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(body.tilt, Eigen::Vector3d::UnitX()))
            .toRotationMatrix();
    markers[m] = position + rotation * offsets_[m];
  }
  return markers;
}

FrameProjector::FrameProjector(const Rig& rig, const ProjectionFaults& faults, uint32_t seed)
    : rig_(rig), faults_(faults), rng_(seed) {
  occluded_until_.resize(rig.cameras.size());
  static_spurious_.resize(rig.cameras.size());
  for (size_t c = 0; c < rig.cameras.size(); ++c) {
    const CameraIntrinsics& in = rig.cameras[c].intrinsics;
    std::uniform_real_distribution<double> x(0.0, in.width), y(0.0, in.height);
    for (int s = 0; s < faults.spurious / 2; ++s) static_spurious_[c].emplace_back(x(rng_), y(rng_));
  }
}

void FrameProjector::Project(uint64_t frame_number, const std::vector<Eigen::Vector3d>& markers,
                             FrameSet* frame_set, BlobTruth* truth) {
  std::normal_distribution<double> noise(0.0, faults_.noise_px);
  std::uniform_real_distribution<double> chance(0.0, 1.0);
  frame_set->frame_number = frame_number;
  frame_set->cameras.clear();
  truth->assign(rig_.cameras.size(), {});
  for (size_t c = 0; c < rig_.cameras.size(); ++c) {
    const Camera& camera = rig_.cameras[c];
    occluded_until_[c].resize(markers.size(), 0);
    CameraFrame frame;
    frame.camera_id = camera.id;
    frame.frame_number = frame_number;
    frame.width = static_cast<uint32_t>(camera.intrinsics.width);
    frame.height = static_cast<uint32_t>(camera.intrinsics.height);
    for (size_t m = 0; m < markers.size(); ++m) {
      Eigen::Vector2d pixel;
      if (!camera.ProjectToPixel(markers[m], &pixel) || !camera.InImage(pixel)) continue;
      if (faults_.occlusion > 0.0 && frame_number >= occluded_until_[c][m] &&
          chance(rng_) < faults_.occlusion) {
        // Geometric lengths with the requested mean.
        std::geometric_distribution<int> length(1.0 / std::max(1, faults_.occlusion_frames));
        occluded_until_[c][m] = frame_number + 1 + static_cast<uint64_t>(length(rng_));
      }
      if (frame_number < occluded_until_[c][m]) continue;
      Blob blob;
      blob.pixel = pixel + Eigen::Vector2d(noise(rng_), noise(rng_));
      blob.area = 20;
      frame.blobs.push_back(blob);
      (*truth)[c].push_back(static_cast<int>(m));
    }
    for (const Eigen::Vector2d& spot : static_spurious_[c]) {
      Blob blob;
      blob.pixel = spot;
      frame.blobs.push_back(blob);
      (*truth)[c].push_back(-1);
    }
    const int flicker = faults_.spurious - faults_.spurious / 2;
    std::uniform_real_distribution<double> x(0.0, camera.intrinsics.width);
    std::uniform_real_distribution<double> y(0.0, camera.intrinsics.height);
    for (int s = 0; s < flicker; ++s) {
      Blob blob;
      blob.pixel = Eigen::Vector2d(x(rng_), y(rng_));
      frame.blobs.push_back(blob);
      (*truth)[c].push_back(-1);
    }
    if (faults_.drop_frames > 0.0 && chance(rng_) < faults_.drop_frames) {
      (*truth)[c].clear();
      continue;
    }
    frame_set->cameras.push_back(std::move(frame));
  }
}

}  // namespace mocap::testing
