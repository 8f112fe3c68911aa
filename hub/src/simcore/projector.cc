// Fault model of the simulator. Occlusion is a two-state Markov chain per (camera, marker) whose
// stationary probability is --occlusion and mean sojourn --occlusion-frames.
#include "simcore/projector.h"

#include "io/marker_trajectories.h"
#include "util/union_find.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <utility>

namespace mocap {
namespace {

constexpr double kPi = 3.14159265358979323846;

// First normalized radius where r * (1 + k1 r^2 + k2 r^4 + k3 r^6) stops increasing.
double MonotonicRadius(const std::array<double, 5>& d) {
  const double step = 1e-3;
  for (double r = step; r < 4.0; r += step) {
    const double r2 = r * r;
    if (1.0 + r2 * (3.0 * d[0] + r2 * (5.0 * d[1] + r2 * 7.0 * d[4])) <= 0.0) return r - step;
  }
  return 4.0;
}

// Shape of a blob made of the spots grouped[begin, end) with this centroid and total area, as
// the node's detector measures it: sqrt(minor / major) of the second moments (a disc of radius r
// contributes r^2 / 4 on every axis), 1 for a round blob. Overlap is counted twice, which makes
// strongly overlapping pairs look a little rounder than a thresholded image would.
double Roundness(const std::vector<FaultyProjector::MarkerImage>& spots,
                 const std::vector<std::pair<int, int>>& grouped, size_t begin, size_t end,
                 const Eigen::Vector2d& centroid, double area) {
  Eigen::Matrix2d moments = Eigen::Matrix2d::Zero();
  for (size_t i = begin; i < end; ++i) {
    const FaultyProjector::MarkerImage& spot = spots[grouped[i].second];
    const double spot_area = kPi * spot.radius * spot.radius;
    const Eigen::Vector2d offset = spot.pixel - centroid;
    moments += spot_area * (0.25 * spot.radius * spot.radius * Eigen::Matrix2d::Identity() + offset * offset.transpose());
  }
  moments /= area;
  const double half_trace = 0.5 * moments.trace();
  const double disc = std::sqrt(0.25 * (moments(0, 0) - moments(1, 1)) * (moments(0, 0) - moments(1, 1)) +
                                moments(0, 1) * moments(0, 1));
  const double major = half_trace + disc, minor = half_trace - disc;
  return major > 0.0 && minor > 0.0 ? std::sqrt(minor / major) : 0.0;
}

void CheckProbability(double value, const char* name) {
  if (!(value >= 0.0 && value <= 1.0)) throw std::invalid_argument(std::string(name) + " must be in [0, 1]");
}

}  // namespace

void ProjectOptions::Check() const {
  if (!(noise_px >= 0.0 && noise_px <= 100.0)) throw std::invalid_argument("--noise-px must be 0..100");
  CheckProbability(occlusion, "--occlusion");
  if (occlusion >= 1.0) throw std::invalid_argument("--occlusion must be below 1");
  if (!(occlusion_frames >= 1.0 && occlusion_frames <= 1e6)) {
    throw std::invalid_argument("--occlusion-frames must be 1..1e6");
  }
  if (!(spurious >= 0.0 && spurious <= 1000.0)) throw std::invalid_argument("--spurious must be 0..1000");
  if (!(merge_px <= 1000.0) || std::isnan(merge_px)) throw std::invalid_argument("--merge-px must be at most 1000");
  if (!(merged_roundness >= 0.0 && merged_roundness <= 1.0)) throw std::invalid_argument("merged roundness must be in [0, 1]");
  CheckProbability(drop_frames, "--drop-frames");
  CheckProbability(late, "--late");
  if (late_frames < 1 || late_frames > 1000) throw std::invalid_argument("--late-frames must be 1..1000");
  if (!(marker_diameter_mm > 0.0 && marker_diameter_mm <= 200.0)) {
    throw std::invalid_argument("--marker-mm must be in (0, 200]");
  }
}

FaultyProjector::FaultyProjector(const Rig& rig, size_t num_markers, const ProjectOptions& options)
    : rig_(rig), num_markers_(num_markers), options_(options) {
  options_.Check();
  occlusion_end_ = 1.0 / options_.occlusion_frames;
  // Stationary probability p = start / (start + end).
  occlusion_start_ = std::min(1.0, options_.occlusion * occlusion_end_ / (1.0 - options_.occlusion));
  const int static_spots = static_cast<int>(std::floor(options_.spurious / 2.0));
  for (size_t i = 0; i < rig_.cameras.size(); ++i) {
    const Camera& camera = rig_.cameras[i];
    CameraState state;
    // One stream per camera: adding a camera or a fault elsewhere does not reshuffle this one.
    std::seed_seq seq{static_cast<uint32_t>(options_.seed), static_cast<uint32_t>(options_.seed >> 32),
                      camera.id, 0x51u};
    state.rng.seed(seq);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    state.valid_radius = MonotonicRadius(camera.intrinsics.distortion);
    state.occluded.resize(num_markers_);
    for (size_t m = 0; m < num_markers_; ++m) state.occluded[m] = unit(state.rng) < options_.occlusion;
    for (int s = 0; s < static_spots; ++s) {
      state.static_spots.emplace_back(unit(state.rng) * camera.intrinsics.width,
                                      unit(state.rng) * camera.intrinsics.height);
    }
    states_.push_back(std::move(state));
  }
}

double FaultyProjector::BlobRadiusPx(const Camera& camera, double depth_mm) const {
  const double focal = 0.5 * (camera.intrinsics.fx + camera.intrinsics.fy);
  // A centroid needs at least one lit pixel.
  return std::max(0.5 * focal * options_.marker_diameter_mm / depth_mm, 0.5);
}

std::vector<CameraFrame> FaultyProjector::Project(uint64_t frame_number, uint64_t trigger_time_ns,
                                                  const Eigen::Vector3d* points,
                                                  std::vector<int>* cameras_seeing,
                                                  std::vector<std::vector<int>>* blob_markers) {
  return Project(frame_number, trigger_time_ns, std::vector<const Eigen::Vector3d*>(rig_.cameras.size(), points),
                 cameras_seeing, blob_markers);
}

std::vector<CameraFrame> FaultyProjector::Project(uint64_t frame_number, uint64_t trigger_time_ns,
                                                  const std::vector<const Eigen::Vector3d*>& camera_points,
                                                  std::vector<int>* cameras_seeing,
                                                  std::vector<std::vector<int>>* blob_markers) {
  if (camera_points.size() != rig_.cameras.size())
    throw std::invalid_argument("one point array per camera is needed");
  cameras_seeing->assign(num_markers_, 0);
  if (blob_markers) blob_markers->clear();
  std::vector<CameraFrame> frames;
  std::vector<int> markers;
  for (size_t i = 0; i < rig_.cameras.size(); ++i) {
    CameraFrame frame;
    markers.clear();
    if (!ProjectCamera(i, frame_number, camera_points[i], cameras_seeing, &frame, &markers)) continue;
    if (blob_markers) blob_markers->push_back(markers);
    frame.trigger_time_ns = trigger_time_ns;
    // Exposure start to readout on a small global-shutter sensor, then detection on the node.
    frame.capture_time_ns = trigger_time_ns + 150000;
    frame.send_time_ns = frame.capture_time_ns + 1500000;
    frames.push_back(std::move(frame));
  }
  return frames;
}

double FaultyProjector::MarkerPeak(double depth_mm) {
  const double brightness = std::clamp(std::pow(2500.0 / depth_mm, 2.0), 0.15, 2.0);
  return std::min(255.0, std::round(60.0 + 180.0 * brightness));
}

std::vector<FaultyProjector::MarkerImage> FaultyProjector::ImageMarkers(size_t index,
                                                                        const Eigen::Vector3d* points) {
  const Camera& camera = rig_.cameras[index];
  CameraState& state = states_[index];
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  // The occlusion chains advance every frame, dropped or not, so they stay continuous in time.
  if (options_.occlusion > 0.0) {
    for (size_t m = 0; m < num_markers_; ++m) {
      const double u = unit(state.rng);
      state.occluded[m] = state.occluded[m] ? (u >= occlusion_end_) : (u < occlusion_start_);
    }
  }
  std::vector<MarkerImage> images;
  for (size_t m = 0; m < num_markers_; ++m) {
    if (MarkerTrajectories::IsGap(points[m]) || state.occluded[m]) continue;
    const Eigen::Vector3d point_in_cam = camera.PointInCamera(points[m]);
    const double depth = point_in_cam.z();
    Eigen::Vector2d pixel;
    if (!camera.ProjectToPixel(points[m], &pixel) || !camera.InImage(pixel)) continue;
    // Barrel distortion folds far-off-axis points back into the image; a real lens never shows
    // them there, so points beyond the model's monotonic range are not seen.
    if ((point_in_cam.head<2>() / depth).norm() > state.valid_radius) continue;
    images.push_back({pixel, BlobRadiusPx(camera, depth), depth, m});
  }
  return images;
}

bool FaultyProjector::ProjectCamera(size_t index, uint64_t frame_number, const Eigen::Vector3d* points,
                                    std::vector<int>* cameras_seeing, CameraFrame* out,
                                    std::vector<int>* blob_markers) {
  const Camera& camera = rig_.cameras[index];
  CameraState& state = states_[index];
  Draws draws;  // one set per camera frame: the normal distribution keeps its second value
  const std::vector<MarkerImage> spots = ImageMarkers(index, points);
  const bool dropped = options_.drop_frames > 0.0 && draws.unit(state.rng) < options_.drop_frames;
  std::vector<int> parent = MergeOverlapping(spots);
  if (dropped) return false;
  // Markers seen only count for frames that reach the hub.
  for (const MarkerImage& spot : spots) ++(*cameras_seeing)[spot.marker];
  out->camera_id = camera.id;
  out->frame_number = frame_number;
  out->width = static_cast<uint32_t>(camera.intrinsics.width);
  out->height = static_cast<uint32_t>(camera.intrinsics.height);
  AddMarkerBlobs(index, spots, std::move(parent), &draws, out, blob_markers);
  AddSpuriousBlobs(index, &draws, out, blob_markers);
  SortInScanlineOrder(out, blob_markers);
  return true;
}

std::vector<int> FaultyProjector::MergeOverlapping(const std::vector<MarkerImage>& spots) const {
  // Blobs that overlap in the image become one (transitively), as thresholding would see them.
  // Sweep in x so only neighbours within the largest possible merge distance are compared.
  double max_radius = 0.0;
  for (const MarkerImage& spot : spots) max_radius = std::max(max_radius, spot.radius);
  const double reach = options_.merge_px >= 0.0 ? options_.merge_px : 2.0 * max_radius;
  std::vector<int> order(spots.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return spots[a].pixel.x() < spots[b].pixel.x(); });
  std::vector<int> parent(spots.size());
  std::iota(parent.begin(), parent.end(), 0);
  for (size_t i = 0; i < order.size(); ++i) {
    const MarkerImage& a = spots[order[i]];
    for (size_t j = i + 1; j < order.size() && spots[order[j]].pixel.x() - a.pixel.x() < reach; ++j) {
      const MarkerImage& b = spots[order[j]];
      const double limit = options_.merge_px >= 0.0 ? options_.merge_px : a.radius + b.radius;
      if ((a.pixel - b.pixel).norm() < limit) parent[FindRoot(parent, order[i])] = FindRoot(parent, order[j]);
    }
  }
  return parent;
}

Eigen::Vector2d FaultyProjector::MeasuredPixel(size_t index, Eigen::Vector2d pixel, Draws* draws) {
  const Camera& camera = rig_.cameras[index];
  std::mt19937_64& rng = states_[index].rng;
  if (options_.noise_px > 0.0) pixel += options_.noise_px * Eigen::Vector2d(draws->gauss(rng), draws->gauss(rng));
  // Noise can push an edge blob off the sensor; a detector would report it on the last pixel.
  // The margin survives the wire's 1/256 px rounding.
  pixel.x() = std::clamp(pixel.x(), 0.0, camera.intrinsics.width - 1.0 / 128.0);
  pixel.y() = std::clamp(pixel.y(), 0.0, camera.intrinsics.height - 1.0 / 128.0);
  return pixel;
}

void FaultyProjector::AddMarkerBlobs(size_t index, const std::vector<MarkerImage>& spots,
                                     std::vector<int> parent, Draws* draws, CameraFrame* frame,
                                     std::vector<int>* blob_markers) {
  const Camera& camera = rig_.cameras[index];
  // Spots grouped by blob (root), in spot order within a group, so the output does not depend on
  // the sweep order.
  std::vector<std::pair<int, int>> grouped(spots.size());
  for (size_t s = 0; s < spots.size(); ++s) grouped[s] = {FindRoot(parent, static_cast<int>(s)), static_cast<int>(s)};
  std::sort(grouped.begin(), grouped.end());
  for (size_t begin = 0; begin < grouped.size();) {
    size_t end = begin;
    double area = 0.0;
    Eigen::Vector2d weighted = Eigen::Vector2d::Zero();
    double nearest = 1e300;
    for (; end < grouped.size() && grouped[end].first == grouped[begin].first; ++end) {
      const MarkerImage& spot = spots[grouped[end].second];
      const double spot_area = kPi * spot.radius * spot.radius;
      area += spot_area;
      weighted += spot_area * spot.pixel;
      nearest = std::min(nearest, spot.depth);
    }
    const size_t members = end - begin;
    const double roundness = Roundness(spots, grouped, begin, end, weighted / area, area);
    blob_markers->push_back(static_cast<int>(spots[grouped[begin].second].marker));
    begin = end;
    Blob blob;
    blob.pixel = MeasuredPixel(index, weighted / area, draws);
    blob.area = static_cast<uint32_t>(std::max(1.0, std::round(area)));
    blob.peak = static_cast<uint32_t>(MarkerPeak(nearest));
    blob.mean = static_cast<uint32_t>(std::round(0.7 * blob.peak));
    if (blob.peak >= 255) blob.flags |= kBlobSaturated;
    // The node flags a blob by its shape alone: two markers that overlap so much that the blob
    // still looks round are not flagged (the hub must cope with those too).
    if (members > 1 && roundness < options_.merged_roundness) blob.flags |= kBlobMerged;
    const double radius = std::sqrt(area / kPi);
    if (blob.pixel.x() < radius || blob.pixel.y() < radius || blob.pixel.x() > camera.intrinsics.width - radius ||
        blob.pixel.y() > camera.intrinsics.height - radius) {
      blob.flags |= kBlobBorder;
    }
    frame->blobs.push_back(blob);
  }
}

void FaultyProjector::AddSpuriousBlobs(size_t index, Draws* draws, CameraFrame* frame,
                                       std::vector<int>* blob_markers) {
  const Camera& camera = rig_.cameras[index];
  CameraState& state = states_[index];
  // False blobs: static reflections keep their place, flicker appears anywhere for one frame.
  const auto add_spurious = [&](const Eigen::Vector2d& pixel) {
    Blob blob;
    blob.pixel = MeasuredPixel(index, pixel, draws);
    blob.area = 1 + static_cast<uint32_t>(draws->unit(state.rng) * 12.0);
    blob.peak = 80 + static_cast<uint32_t>(draws->unit(state.rng) * 175.0);
    blob.mean = static_cast<uint32_t>(0.7 * blob.peak);
    frame->blobs.push_back(blob);
    blob_markers->push_back(-1);
  };
  for (const Eigen::Vector2d& spot : state.static_spots) add_spurious(spot);
  const double flicker_mean = options_.spurious - static_cast<double>(state.static_spots.size());
  if (flicker_mean > 0.0) {
    std::poisson_distribution<int> flicker(flicker_mean);
    const int count = flicker(state.rng);
    for (int k = 0; k < count; ++k) {
      add_spurious(Eigen::Vector2d(draws->unit(state.rng) * camera.intrinsics.width,
                                   draws->unit(state.rng) * camera.intrinsics.height));
    }
  }
}

void FaultyProjector::SortInScanlineOrder(CameraFrame* frame, std::vector<int>* blob_markers) {
  // Detectors report blobs in scanline order, which carries no marker identity (the markers of
  // the blobs follow their blobs).
  std::vector<size_t> scanline(frame->blobs.size());
  std::iota(scanline.begin(), scanline.end(), size_t{0});
  std::sort(scanline.begin(), scanline.end(), [&](size_t i, size_t j) {
    const Eigen::Vector2d& a = frame->blobs[i].pixel;
    const Eigen::Vector2d& b = frame->blobs[j].pixel;
    if (a.y() != b.y()) return a.y() < b.y();
    return a.x() != b.x() ? a.x() < b.x() : i < j;
  });
  std::vector<Blob> blobs(scanline.size());
  std::vector<int> markers(scanline.size());
  for (size_t k = 0; k < scanline.size(); ++k) {
    blobs[k] = frame->blobs[scanline[k]];
    markers[k] = (*blob_markers)[scanline[k]];
  }
  frame->blobs.swap(blobs);
  blob_markers->swap(markers);
}

}  // namespace mocap
