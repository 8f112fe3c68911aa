// A knocked camera found again: shift vote, candidate pairs, PnP + RANSAC, narrowing re-pairing.
#include "calib/camera_relocalization.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>

#include <ceres/loss_function.h>
#include <ceres/problem.h>
#include <ceres/solver.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include <Eigen/Geometry>

#include "calib/camera_blocks.h"
#include "calib/cost_functions.h"

namespace mocap {

void CameraRelocalizationOptions::Check() const {
  auto positive = [](double value, const char* name) {
    if (!(value > 0.0) || !std::isfinite(value)) throw std::invalid_argument(std::string(name) + " must be > 0");
  };
  positive(search_px, "relocalization search_px");
  positive(vote_bin_px, "relocalization vote_bin_px");
  positive(match_px, "relocalization match_px");
  positive(ransac_px, "relocalization ransac_px");
  positive(loss_scale_px, "relocalization loss_scale_px");
  positive(outlier_px, "relocalization outlier_px");
  if (search_px / vote_bin_px > 500.0)
    throw std::invalid_argument("relocalization search_px / vote_bin_px must be <= 500 (the vote's grid)");
  if (max_vote_frames < 1) throw std::invalid_argument("relocalization max_vote_frames must be >= 1");
  if (!(ambiguity_ratio >= 1.0) || !std::isfinite(ambiguity_ratio))
    throw std::invalid_argument("relocalization ambiguity_ratio must be >= 1");
  if (ransac_iterations < 1) throw std::invalid_argument("relocalization ransac_iterations must be >= 1");
  if (max_candidates < 6) throw std::invalid_argument("relocalization max_candidates must be >= 6");
  if (min_inliers < 6) throw std::invalid_argument("relocalization min_inliers must be >= 6");
  if (!(min_inlier_fraction >= 0.0 && min_inlier_fraction < 1.0))
    throw std::invalid_argument("relocalization min_inlier_fraction must be within [0, 1)");
  if (max_iterations < 1) throw std::invalid_argument("relocalization max_iterations must be >= 1");
}

int UnambiguousNearestBlob(const std::vector<Eigen::Vector2d>& blobs, const Eigen::Vector2d& predicted,
                           double gate_px, double ambiguity_ratio) {
  double best = std::numeric_limits<double>::infinity(), second = best;
  int best_blob = -1;
  for (size_t b = 0; b < blobs.size(); ++b) {
    const double d = (blobs[b] - predicted).norm();
    if (d < best) {
      second = best;
      best = d;
      best_blob = static_cast<int>(b);
    } else if (d < second) {
      second = d;
    }
  }
  if (best_blob < 0 || best > gate_px || second < ambiguity_ratio * best) return -1;
  return best_blob;
}

namespace {

double Median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

// The points the unmoved cameras triangulate in one frame, with that frame's blobs.
struct FramePoints {
  const std::vector<Eigen::Vector2d>* blobs = nullptr;
  std::vector<Eigen::Vector3d> points;
};

struct Correspondence {
  Eigen::Vector3d point;
  Eigen::Vector2d pixel;
};

class Relocalizer {
 public:
  Relocalizer(const Rig& rig, size_t camera, const CameraRelocalizationOptions& options)
      : camera_(rig.cameras[camera]), index_(camera), options_(options) {}

  CameraRelocalization Run(const Rig& rig, const std::vector<char>& excluded, const std::deque<MarkerSample>& samples,
                           const std::deque<FrameBlobs>& blobs) {
    CameraRelocalization result;
    result.camera = camera_;
    const std::string name = "camera " + std::to_string(camera_.id);
    GatherFrames(rig, excluded, samples, blobs, &result.points);
    if (frames_.empty()) {
      result.reason = name + ": no frame with both its blobs and markers the unmoved cameras triangulate; "
                             "capture the subject where this camera and two unmoved ones see it";
      return result;
    }
    if (!Vote(&result.shift_px)) {
      result.reason = name + ": none of its blobs lies within " + Format(options_.search_px) +
                      " px of where the old pose puts the markers (moved further, or not seeing the subject); "
                      "calibrate with the wand again";
      return result;
    }
    std::vector<Correspondence> candidates = Match(camera_, result.shift_px, options_.match_px);
    if (candidates.size() > options_.max_candidates) {
      std::vector<Correspondence> spread;
      const double step = static_cast<double>(candidates.size()) / static_cast<double>(options_.max_candidates);
      for (size_t i = 0; i < options_.max_candidates; ++i) spread.push_back(candidates[static_cast<size_t>(i * step)]);
      candidates = std::move(spread);
    }
    result.candidates = candidates.size();
    Camera pose = camera_;
    if (candidates.size() < options_.min_inliers || !SolvePnP(candidates, &pose, &result.ransac_inliers) ||
        result.ransac_inliers < options_.min_inliers ||
        static_cast<double>(result.ransac_inliers) < options_.min_inlier_fraction * static_cast<double>(candidates.size())) {
      result.reason = name + ": only " + std::to_string(result.ransac_inliers) + " of " +
                      std::to_string(result.candidates) + " candidate marker pairings agree on one pose (at least " +
                      std::to_string(options_.min_inliers) + " and " +
                      std::to_string(static_cast<int>(100.0 * options_.min_inlier_fraction)) +
                      " % needed); capture longer with the subject in its view, or calibrate with the wand again";
      return result;
    }
    double gate = std::max(2.0 * options_.ransac_px, 4.0 * options_.outlier_px);
    std::vector<Correspondence> matched;
    for (int round = 0; round < 4; ++round) {
      matched = Match(pose, Eigen::Vector2d::Zero(), gate);
      if (matched.size() < options_.min_inliers) break;
      Resect(matched, &pose);
      std::vector<double> lengths = Residuals(pose, matched);
      gate = std::max(options_.outlier_px, 5.0 * 1.4826 * Median(lengths));
    }
    matched = Match(pose, Eigen::Vector2d::Zero(), gate);
    result.gate_px = gate;
    result.inliers = matched.size();
    result.median_px = Median(Residuals(pose, matched));
    if (matched.size() < options_.min_inliers) {
      result.reason = name + ": the pose RANSAC found keeps only " + std::to_string(matched.size()) +
                      " marker views within " + Format(gate) + " px (" + std::to_string(options_.min_inliers) +
                      " needed); capture longer with the subject in its view, or calibrate with the wand again";
      return result;
    }
    result.camera = pose;
    result.ok = true;
    return result;
  }

 private:
  static std::string Format(double value) {
    char text[32];
    std::snprintf(text, sizeof(text), "%.3g", value);
    return text;
  }

  void GatherFrames(const Rig& rig, const std::vector<char>& excluded, const std::deque<MarkerSample>& samples,
                    const std::deque<FrameBlobs>& blobs, size_t* points) {
    size_t next_blobs = 0;
    for (const MarkerSample& sample : samples) {
      while (next_blobs < blobs.size() && blobs[next_blobs].frame < sample.frame) ++next_blobs;
      if (next_blobs == blobs.size() || blobs[next_blobs].frame != sample.frame) continue;
      const FrameBlobs& frame = blobs[next_blobs];
      if (index_ >= frame.pixels.size() || frame.pixels[index_].empty()) continue;
      Eigen::Vector3d point;
      if (!LeaveOneOutPoint(rig, sample, -1, excluded, &point)) continue;
      if (frames_.empty() || frames_.back().blobs != &frame.pixels[index_]) {
        frames_.emplace_back();
        frames_.back().blobs = &frame.pixels[index_];
      }
      frames_.back().points.push_back(point);
      ++*points;
    }
  }

  // The image shift most (projected point, blob) pairs agree on: a knock moves all of a
  // camera's markers by nearly one shift, wrong pairs spread over the whole range.
  bool Vote(Eigen::Vector2d* shift) const {
    const double range = options_.search_px;
    const int half = static_cast<int>(std::ceil(range / options_.vote_bin_px));
    const int side = 2 * half + 1;
    std::vector<double> count(static_cast<size_t>(side * side), 0.0), sum_x(count), sum_y(count);
    const size_t stride = std::max<size_t>(1, (frames_.size() + options_.max_vote_frames - 1) / options_.max_vote_frames);
    for (size_t f = 0; f < frames_.size(); f += stride) {
      for (const Eigen::Vector3d& point : frames_[f].points) {
        Eigen::Vector2d projected;
        if (!camera_.ProjectToPixel(point, &projected)) continue;
        for (const Eigen::Vector2d& blob : *frames_[f].blobs) {
          const Eigen::Vector2d d = blob - projected;
          if (std::abs(d.x()) > range || std::abs(d.y()) > range) continue;
          const int ix = std::clamp(static_cast<int>(std::lround(d.x() / options_.vote_bin_px)) + half, 0, side - 1);
          const int iy = std::clamp(static_cast<int>(std::lround(d.y() / options_.vote_bin_px)) + half, 0, side - 1);
          const size_t cell = static_cast<size_t>(iy * side + ix);
          count[cell] += 1.0;
          sum_x[cell] += d.x();
          sum_y[cell] += d.y();
        }
      }
    }
    double best = 0.0;
    Eigen::Vector2d best_shift = Eigen::Vector2d::Zero();
    for (int iy = 0; iy < side; ++iy) {
      for (int ix = 0; ix < side; ++ix) {
        double n = 0.0, x = 0.0, y = 0.0;
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dx = -1; dx <= 1; ++dx) {
            const int cx = ix + dx, cy = iy + dy;
            if (cx < 0 || cy < 0 || cx >= side || cy >= side) continue;
            const size_t cell = static_cast<size_t>(cy * side + cx);
            n += count[cell];
            x += sum_x[cell];
            y += sum_y[cell];
          }
        }
        if (n > best) {
          best = n;
          best_shift = Eigen::Vector2d(x / n, y / n);
        }
      }
    }
    *shift = best_shift;
    return best > 0.0;
  }

  // Each point's unambiguous nearest blob around its projection under `pose` plus `shift`;
  // a blob two points claim is dropped for both.
  std::vector<Correspondence> Match(const Camera& pose, const Eigen::Vector2d& shift, double gate) const {
    std::vector<Correspondence> matched;
    std::vector<int> blob_of;
    std::vector<int> claims;
    for (const FramePoints& frame : frames_) {
      blob_of.assign(frame.points.size(), -1);
      claims.assign(frame.blobs->size(), 0);
      for (size_t p = 0; p < frame.points.size(); ++p) {
        Eigen::Vector2d projected;
        if (!pose.ProjectToPixel(frame.points[p], &projected)) continue;
        blob_of[p] = UnambiguousNearestBlob(*frame.blobs, projected + shift, gate, options_.ambiguity_ratio);
        if (blob_of[p] >= 0) ++claims[static_cast<size_t>(blob_of[p])];
      }
      for (size_t p = 0; p < frame.points.size(); ++p) {
        if (blob_of[p] < 0 || claims[static_cast<size_t>(blob_of[p])] != 1) continue;
        matched.push_back({frame.points[p], (*frame.blobs)[static_cast<size_t>(blob_of[p])]});
      }
    }
    return matched;
  }

  // PnP + RANSAC on undistorted normalized coordinates (the lens is known and did not change).
  bool SolvePnP(const std::vector<Correspondence>& candidates, Camera* pose, size_t* inliers) const {
    std::vector<cv::Point3d> object;
    std::vector<cv::Point2d> image;
    object.reserve(candidates.size());
    image.reserve(candidates.size());
    for (const Correspondence& c : candidates) {
      object.emplace_back(c.point.x(), c.point.y(), c.point.z());
      const Eigen::Vector2d normalized = camera_.UndistortPixel(c.pixel);
      image.emplace_back(normalized.x(), normalized.y());
    }
    cv::Mat rvec, tvec;
    std::vector<int> inlier_index;
    const double threshold = options_.ransac_px / camera_.intrinsics.fx;
    bool ok = false;
    try {
      ok = cv::solvePnPRansac(object, image, cv::Mat::eye(3, 3, CV_64F), cv::noArray(), rvec, tvec, false,
                              options_.ransac_iterations, static_cast<float>(threshold), 0.999, inlier_index,
                              cv::SOLVEPNP_AP3P);
    } catch (const cv::Exception&) {
      ok = false;  // degenerate candidates: reported as too few agreeing
    }
    *inliers = ok ? inlier_index.size() : 0;
    if (!ok) return false;
    cv::Mat rotation;
    cv::Rodrigues(rvec, rotation);
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) pose->rotation(r, c) = rotation.at<double>(r, c);
      pose->translation(r) = tvec.at<double>(r);
    }
    return pose->rotation.allFinite() && pose->translation.allFinite();
  }

  void Resect(const std::vector<Correspondence>& matched, Camera* pose) const {
    std::array<double, kPoseSize> block = PoseBlock(*pose);
    std::array<double, kIntrinsicsSize> intrinsics = IntrinsicsBlock(pose->intrinsics);
    ceres::Problem problem;
    for (const Correspondence& c : matched) {
      problem.AddResidualBlock(KnownPointReprojectionError::Create(c.point, c.pixel),
                               new ceres::HuberLoss(options_.loss_scale_px), block.data(), intrinsics.data());
    }
    problem.SetParameterBlockConstant(intrinsics.data());
    ceres::Solver::Options solver;
    solver.linear_solver_type = ceres::DENSE_QR;
    solver.max_num_iterations = options_.max_iterations;
    solver.function_tolerance = 1e-12;
    solver.gradient_tolerance = 1e-14;
    solver.parameter_tolerance = 1e-12;
    solver.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    ceres::Solve(solver, &problem, &summary);
    SetPoseFromBlock(block.data(), pose);
  }

  static std::vector<double> Residuals(const Camera& pose, const std::vector<Correspondence>& matched) {
    std::vector<double> lengths;
    lengths.reserve(matched.size());
    for (const Correspondence& c : matched) {
      Eigen::Vector2d projected;
      if (pose.ProjectToPixel(c.point, &projected)) lengths.push_back((projected - c.pixel).norm());
    }
    return lengths;
  }

  const Camera camera_;
  const size_t index_;
  const CameraRelocalizationOptions& options_;
  std::vector<FramePoints> frames_;
};

}  // namespace

CameraRelocalization RelocalizeCamera(const Rig& rig, size_t camera, const std::vector<char>& excluded,
                                      const std::deque<MarkerSample>& samples, const std::deque<FrameBlobs>& blobs,
                                      const CameraRelocalizationOptions& options) {
  options.Check();
  if (camera >= rig.cameras.size()) throw std::invalid_argument("RelocalizeCamera: camera index out of range");
  return Relocalizer(rig, camera, options).Run(rig, excluded, samples, blobs);
}

}  // namespace mocap
