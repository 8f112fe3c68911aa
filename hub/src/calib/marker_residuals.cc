// Reconstructed markers with their views, and per-camera leave-one-out residuals.
#include "calib/marker_residuals.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "geometry/triangulation.h"

namespace mocap {

void MarkerResidualOptions::Check() const {
  if (min_views < 2) throw std::invalid_argument("min_views must be >= 2");
  if (!(max_point_rms_px > 0.0)) throw std::invalid_argument("max_point_rms_px must be > 0");
  if (!(search_px > 0.0) || !std::isfinite(search_px)) throw std::invalid_argument("search_px must be > 0");
  if (!(ambiguity_ratio >= 1.0) || !std::isfinite(ambiguity_ratio))
    throw std::invalid_argument("ambiguity_ratio must be >= 1");
  if (max_samples < 1) throw std::invalid_argument("max_samples must be >= 1");
  if (max_blob_frames < 1) throw std::invalid_argument("max_blob_frames must be >= 1");
}

MarkerResidualCollector::MarkerResidualCollector(const Rig& rig, const MarkerResidualOptions& options,
                                                 const ReconstructorOptions& recon)
    : rig_(rig), options_((options.Check(), options)), recon_((recon.Check(), recon)) {
  recon_.follow_measured_noise = false;
}

void MarkerResidualCollector::Add(const FrameSet& set) {
  if (!reconstructor_) reconstructor_ = std::make_unique<Reconstructor>(rig_, recon_);
  reconstructor_->Process(set, {}, &points_);
  AddReconstructed(set, *reconstructor_);
}

void MarkerResidualCollector::DropBefore(uint64_t frame) {
  while (!samples_.empty() && samples_.front().frame < frame) samples_.pop_front();
  while (!blobs_.empty() && blobs_.front().frame < frame) blobs_.pop_front();
}

void MarkerResidualCollector::AddReconstructed(const FrameSet& set, const Reconstructor& reconstructor) {
  ++frames_;
  const RigModel& model = reconstructor.rig_model();
  const FrameViews& views = reconstructor.views();
  frame_of_camera_.assign(rig_.cameras.size(), nullptr);
  for (const CameraFrame& frame : set.cameras) {
    const int index = model.IndexOf(frame.camera_id);
    if (index >= 0) frame_of_camera_[index] = &frame;
  }
  const std::vector<TriangulatedPoint>& triangulated = reconstructor.triangulated();
  size_t added = 0;
  for (size_t p = 0; p < triangulated.size(); ++p) {
    const TriangulatedPoint& point = triangulated[p];
    if (static_cast<int>(point.observations.size()) < options_.min_views) continue;
    if (!(point.rms_px <= options_.max_point_rms_px)) continue;
    MarkerSample sample;
    sample.frame = set.frame_number;
    sample.point_in_world = point.point_in_world;
    std::vector<char> has_view(rig_.cameras.size(), 0);
    for (int o : point.observations) {
      const Observation& observation = views.observations[o];
      const CameraFrame* frame = frame_of_camera_[observation.camera];
      if (frame == nullptr || observation.blob >= static_cast<int>(frame->blobs.size())) continue;
      MarkerView view;
      view.camera = observation.camera;
      view.pixel = frame->blobs[observation.blob].pixel;
      view.normalized = observation.normalized;
      view.reconstructed = true;
      sample.views.push_back(view);
      has_view[observation.camera] = 1;
    }
    for (size_t c = 0; c < rig_.cameras.size(); ++c) {
      const CameraFrame* frame = frame_of_camera_[c];
      if (has_view[c] || frame == nullptr) continue;
      const Camera& camera = rig_.cameras[c];
      Eigen::Vector2d projected;
      if (!camera.ProjectToPixel(point.point_in_world, &projected) || !camera.InImage(projected)) continue;
      double best = std::numeric_limits<double>::infinity(), second = best;
      int best_blob = -1;
      for (size_t b = 0; b < frame->blobs.size(); ++b) {
        const double d = (frame->blobs[b].pixel - projected).norm();
        if (d < best) {
          second = best;
          best = d;
          best_blob = static_cast<int>(b);
        } else if (d < second) {
          second = d;
        }
      }
      if (best_blob < 0 || best > options_.search_px || second < options_.ambiguity_ratio * best) continue;
      MarkerView view;
      view.camera = static_cast<int>(c);
      view.pixel = frame->blobs[best_blob].pixel;
      view.normalized = camera.UndistortPixel(view.pixel);
      view.reconstructed = false;
      sample.views.push_back(view);
    }
    samples_.push_back(std::move(sample));
    ++added;
    while (samples_.size() > options_.max_samples) samples_.pop_front();
  }
  if (added == 0) return;
  FrameBlobs blobs;
  blobs.frame = set.frame_number;
  blobs.pixels.resize(rig_.cameras.size());
  for (size_t c = 0; c < rig_.cameras.size(); ++c) {
    if (frame_of_camera_[c] == nullptr) continue;
    blobs.pixels[c].reserve(frame_of_camera_[c]->blobs.size());
    for (const Blob& blob : frame_of_camera_[c]->blobs) blobs.pixels[c].push_back(blob.pixel);
  }
  blobs_.push_back(std::move(blobs));
  while (blobs_.size() > options_.max_blob_frames) blobs_.pop_front();
}

PointView ViewThrough(const Camera& camera, const Eigen::Vector2d& normalized) {
  PointView view;
  view.cam_from_world.leftCols<3>() = camera.rotation;
  view.cam_from_world.col(3) = camera.translation;
  view.normalized = normalized;
  return view;
}

bool LeaveOneOutPoint(const Rig& rig, const MarkerSample& sample, int skip, const std::vector<char>& excluded,
                      Eigen::Vector3d* point_in_world) {
  std::vector<PointView> views;
  views.reserve(sample.views.size());
  for (int v = 0; v < static_cast<int>(sample.views.size()); ++v) {
    const MarkerView& view = sample.views[v];
    if (v == skip || !view.reconstructed) continue;
    if (!excluded.empty() && excluded[view.camera]) continue;
    views.push_back(ViewThrough(rig.cameras[view.camera], view.normalized));
  }
  if (views.size() < 2) return false;
  return TriangulatePoint(views, point_in_world);
}

std::vector<CameraResiduals> ComputeCameraResiduals(const Rig& rig, const std::deque<MarkerSample>& samples) {
  const size_t n = rig.cameras.size();
  std::vector<std::vector<double>> lengths(n);
  std::vector<CameraResiduals> result(n);
  for (size_t c = 0; c < n; ++c) result[c].camera_id = rig.cameras[c].id;
  const std::vector<char> none;
  for (const MarkerSample& sample : samples) {
    for (int v = 0; v < static_cast<int>(sample.views.size()); ++v) {
      const MarkerView& view = sample.views[v];
      Eigen::Vector3d point;
      if (!LeaveOneOutPoint(rig, sample, v, none, &point)) continue;
      Eigen::Vector2d projected;
      if (!rig.cameras[view.camera].ProjectToPixel(point, &projected)) continue;
      const Eigen::Vector2d residual = view.pixel - projected;
      CameraResiduals& r = result[view.camera];
      ++r.observations;
      r.reconstructed += view.reconstructed;
      r.mean_px += residual;
      r.rms_px += residual.squaredNorm();
      lengths[view.camera].push_back(residual.norm());
    }
  }
  for (size_t c = 0; c < n; ++c) {
    CameraResiduals& r = result[c];
    if (r.observations == 0) continue;
    r.mean_px /= static_cast<double>(r.observations);
    r.rms_px = std::sqrt(r.rms_px / static_cast<double>(r.observations));
    std::vector<double>& l = lengths[c];
    std::nth_element(l.begin(), l.begin() + l.size() / 2, l.end());
    r.median_px = l[l.size() / 2];
  }
  return result;
}

}  // namespace mocap
