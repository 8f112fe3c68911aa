// Single-marker wanding: views, the camera-pair graph chained by essential matrices, bundle
// adjustment with the scale gauge held, then the scale from two-blob frames.
#include "calib/single_marker_calibration.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <stdexcept>

#include <ceres/loss_function.h>
#include <ceres/manifold.h>
#include <ceres/problem.h>
#include <ceres/product_manifold.h>
#include <ceres/solver.h>
#include <ceres/sphere_manifold.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "calib/camera_blocks.h"
#include "calib/marker_reprojection_error.h"
#include "geometry/triangulation.h"

namespace mocap {

void SingleMarkerOptions::Check() const {
  if (!(scale_length_mm >= 10.0 && scale_length_mm <= 10000.0))
    throw std::invalid_argument("the scale length (--scale-length) must be 10..10000 mm");
  selection.Check();
  if (min_pair_frames < 8) throw std::invalid_argument("min_pair_frames must be >= 8");
  for (double v : {ransac_px, loss_scale_px, outlier_px}) {
    if (!(v > 0.0) || !std::isfinite(v)) throw std::invalid_argument("ransac_px, loss_scale_px and outlier_px must be > 0");
  }
  if (min_scale_frames < 1) throw std::invalid_argument("min_scale_frames must be >= 1");
  if (max_frames < 100) throw std::invalid_argument("max_frames must be >= 100");
  if (max_iterations < 1 || num_threads < 1) throw std::invalid_argument("max_iterations and num_threads must be >= 1");
}

namespace {

double Median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

Eigen::Matrix<double, 3, 4> Projection(const Camera& camera) {
  Eigen::Matrix<double, 3, 4> p;
  p.leftCols<3>() = camera.rotation;
  p.col(3) = camera.translation;
  return p;
}

// Sampson distance of a normalized correspondence under essential matrix e (x2' E x1 = 0).
double Sampson(const Eigen::Matrix3d& e, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector3d x1(a.x(), a.y(), 1.0), x2(b.x(), b.y(), 1.0);
  const Eigen::Vector3d ex1 = e * x1, etx2 = e.transpose() * x2;
  const double num = x2.dot(ex1);
  const double den = ex1.head<2>().squaredNorm() + etx2.head<2>().squaredNorm();
  return den > 0.0 ? num * num / den : 0.0;
}

class SingleMarkerSolver {
 public:
  SingleMarkerSolver(const std::vector<FrameSet>& frames, const Rig& intrinsics, const SingleMarkerOptions& options)
      : frames_(frames), options_(options), rig_(intrinsics), posed_(intrinsics.cameras.size(), 0) {}

  SingleMarkerResult Run() {
    if (rig_.cameras.size() < 2) throw std::runtime_error("a calibration needs at least two cameras");
    SelectViews();
    JoinCameras();
    BundleAdjust();
    Scale();
    return Report();
  }

 private:
  // Stage 1: frames with the single marker in two or more cameras (spread evenly over at most
  // max_frames), and per camera frame its view index.
  void SelectViews() {
    WandSelectionStats stats;
    std::vector<WandFrame> all = SelectWandFrames(frames_, rig_, WandGeometry::SingleMarker(), options_.selection, &stats);
    result_.frames_selected = all.size();
    const size_t stride = std::max<size_t>(1, (all.size() + options_.max_frames - 1) / options_.max_frames);
    for (size_t f = 0; f < all.size(); f += stride) frames_used_.push_back(std::move(all[f]));
    views_.assign(rig_.cameras.size(), 0);
    for (const WandFrame& frame : frames_used_) {
      for (const WandView& view : frame.views) ++views_[view.camera];
    }
    if (frames_used_.size() < static_cast<size_t>(options_.min_pair_frames))
      throw std::runtime_error("only " + std::to_string(frames_used_.size()) +
                               " frames show a single marker in two or more cameras (a camera frame counts when it "
                               "has exactly one blob); wave one marker through the volume for longer");
  }

  // The frames cameras a and b both see, as pairs of normalized points.
  void Shared(size_t a, size_t b, std::vector<size_t>* frames, std::vector<Eigen::Vector2d>* pa,
              std::vector<Eigen::Vector2d>* pb) const {
    for (size_t f = 0; f < frames_used_.size(); ++f) {
      const WandView* va = nullptr;
      const WandView* vb = nullptr;
      for (const WandView& v : frames_used_[f].views) {
        if (v.camera == a) va = &v;
        if (v.camera == b) vb = &v;
      }
      if (va == nullptr || vb == nullptr) continue;
      frames->push_back(f);
      pa->push_back(va->normalized[0]);
      pb->push_back(vb->normalized[0]);
    }
  }

  // Stage 2. Relative pose b_from_a with a unit baseline, from the pair's essential matrix;
  // false with the reason when the pair does not give one.
  bool RelativePose(size_t a, size_t b, std::vector<size_t>* frames, Eigen::Matrix3d* rotation,
                    Eigen::Vector3d* direction, std::vector<char>* inlier, std::string* why) const {
    std::vector<Eigen::Vector2d> pa, pb;
    Shared(a, b, frames, &pa, &pb);
    if (static_cast<int>(frames->size()) < options_.min_pair_frames) {
      *why = "shares " + std::to_string(frames->size()) + " frames";
      return false;
    }
    std::vector<cv::Point2d> p1, p2;
    for (size_t i = 0; i < pa.size(); ++i) {
      p1.emplace_back(pa[i].x(), pa[i].y());
      p2.emplace_back(pb[i].x(), pb[i].y());
    }
    const double focal = 0.5 * (rig_.cameras[a].intrinsics.fx + rig_.cameras[b].intrinsics.fx);
    const cv::Mat identity = cv::Mat::eye(3, 3, CV_64F);
    cv::Mat mask;
    const cv::Mat e = cv::findEssentialMat(p1, p2, identity, cv::RANSAC, 0.999, options_.ransac_px / focal, 2000, mask);
    if (e.rows != 3 || e.cols != 3) {
      *why = "no essential matrix";
      return false;
    }
    cv::Mat r, t;
    const int in_front = cv::recoverPose(e, p1, p2, identity, r, t, mask);
    if (in_front < options_.min_pair_frames) {
      *why = std::to_string(in_front) + " frames in front of both cameras";
      return false;
    }
    cv::cv2eigen(r, *rotation);
    cv::cv2eigen(t, *direction);
    inlier->assign(frames->size(), 0);
    for (size_t i = 0; i < frames->size(); ++i) (*inlier)[i] = mask.at<uchar>(static_cast<int>(i)) != 0;
    return true;
  }

  void JoinCameras() {
    const size_t n = rig_.cameras.size();
    const size_t reference = static_cast<size_t>(std::max_element(views_.begin(), views_.end()) - views_.begin());
    reference_ = reference;
    rig_.cameras[reference].rotation.setIdentity();
    rig_.cameras[reference].translation.setZero();
    posed_[reference] = 1;
    joined_through_.assign(n, 0);
    for (size_t joined = 1; joined < n; ++joined) {
      // The unposed camera and posed partner that share the most frames; after the first pair,
      // the most frames a third posed camera sees too (they chain the baseline's length).
      std::vector<int> posed_views(frames_used_.size(), 0);
      for (size_t f = 0; f < frames_used_.size(); ++f) {
        for (const WandView& v : frames_used_[f].views) posed_views[f] += posed_[v.camera];
      }
      size_t best_a = n, best_b = n, best_count = 0;
      for (size_t b = 0; b < n; ++b) {
        if (posed_[b]) continue;
        for (size_t a = 0; a < n; ++a) {
          if (!posed_[a]) continue;
          std::vector<size_t> frames;
          std::vector<Eigen::Vector2d> pa, pb;
          Shared(a, b, &frames, &pa, &pb);
          size_t count = frames.size();
          if (joined > 1) {
            count = 0;
            for (size_t f : frames) count += posed_views[f] >= 2;
          }
          if (count > best_count) {
            best_count = count;
            best_a = a;
            best_b = b;
          }
        }
      }
      if (best_b == n) break;
      std::vector<size_t> frames;
      std::vector<char> inlier;
      Eigen::Matrix3d rotation;
      Eigen::Vector3d direction;
      std::string why;
      if (!RelativePose(best_a, best_b, &frames, &rotation, &direction, &inlier, &why)) {
        throw std::runtime_error("camera " + std::to_string(rig_.cameras[best_b].id) + " cannot join: with camera " +
                                 std::to_string(rig_.cameras[best_a].id) + " (the posed camera it shares most with) it " +
                                 why + " (" + std::to_string(options_.min_pair_frames) +
                                 " needed); wave the marker where both see it");
      }
      const Camera& partner = rig_.cameras[best_a];
      double scale = 1.0;
      if (joined > 1) {
        // The baseline's length: depths in the partner of the points the posed cameras
        // triangulate, against the same frames triangulated by the pair with a unit baseline.
        Eigen::Matrix<double, 3, 4> first = Eigen::Matrix<double, 3, 4>::Zero();
        first.leftCols<3>().setIdentity();
        Eigen::Matrix<double, 3, 4> second;
        second.leftCols<3>() = rotation;
        second.col(3) = direction;
        std::vector<double> ratios;
        for (size_t i = 0; i < frames.size(); ++i) {
          Eigen::Vector3d known;
          if (!inlier[i] || !TriangulatePosed(frames[i], &known)) continue;
          const WandFrame& frame = frames_used_[frames[i]];
          Eigen::Vector2d in_a = Eigen::Vector2d::Zero(), in_b = Eigen::Vector2d::Zero();
          for (const WandView& v : frame.views) {
            if (v.camera == best_a) in_a = v.normalized[0];
            if (v.camera == best_b) in_b = v.normalized[0];
          }
          Eigen::Vector3d pair_point;
          if (!TriangulatePoint({{first, in_a}, {second, in_b}}, &pair_point) || !(pair_point.z() > 0.0)) continue;
          const double depth = partner.PointInCamera(known).z();
          if (depth > 0.0) ratios.push_back(depth / pair_point.z());
        }
        if (ratios.size() < static_cast<size_t>(options_.min_pair_frames) / 2)
          throw std::runtime_error("camera " + std::to_string(rig_.cameras[best_b].id) +
                                   " cannot join: too few of its frames with camera " + std::to_string(partner.id) +
                                   " are seen by a third posed camera (" + std::to_string(ratios.size()) +
                                   "); wave the marker where three cameras see it");
        scale = Median(ratios);
      }
      Camera& camera = rig_.cameras[best_b];
      camera.rotation = rotation * partner.rotation;
      camera.translation = rotation * partner.translation + scale * direction;
      posed_[best_b] = 1;
      joined_through_[best_b] = partner.id;
      if (joined == 1) first_joiner_ = best_b;
    }
    for (size_t c = 0; c < n; ++c) {
      if (!posed_[c])
        throw std::runtime_error("camera " + std::to_string(rig_.cameras[c].id) + " shares no frame with the others (" +
                                 std::to_string(views_[c]) + " single-marker views); wave the marker in its view");
    }
  }

  // The frame's point from every posed camera's view; false with fewer than two.
  bool TriangulatePosed(size_t f, Eigen::Vector3d* point) const {
    std::vector<PointView> views;
    for (const WandView& v : frames_used_[f].views) {
      if (posed_[v.camera]) views.push_back({Projection(rig_.cameras[v.camera]), v.normalized[0]});
    }
    return views.size() >= 2 && TriangulatePoint(views, point);
  }

  // Stage 3.
  void BundleAdjust() {
    const size_t n = rig_.cameras.size();
    std::vector<std::array<double, kPoseSize>> poses(n);
    std::vector<std::array<double, kIntrinsicsSize>> intrinsics(n);
    for (size_t c = 0; c < n; ++c) {
      poses[c] = PoseBlock(rig_.cameras[c]);
      intrinsics[c] = IntrinsicsBlock(rig_.cameras[c].intrinsics);
    }
    points_.assign(frames_used_.size(), {});
    has_point_.assign(frames_used_.size(), 0);
    active_.assign(frames_used_.size(), {});
    for (size_t f = 0; f < frames_used_.size(); ++f) {
      Eigen::Vector3d p;
      if (!TriangulatePosed(f, &p)) continue;
      points_[f] = {p.x(), p.y(), p.z()};
      has_point_[f] = 1;
      active_[f].assign(frames_used_[f].views.size(), 1);
    }
    const std::unique_ptr<ceres::LossFunction> loss(new ceres::HuberLoss(options_.loss_scale_px));
    for (int pass = 0; pass < 2; ++pass) {
      ceres::Problem::Options problem_options;
      problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
      ceres::Problem problem(problem_options);
      for (size_t f = 0; f < frames_used_.size(); ++f) {
        if (!has_point_[f]) continue;
        size_t used = 0;
        for (size_t v = 0; v < frames_used_[f].views.size(); ++v) used += active_[f][v];
        if (used < 2) continue;
        for (size_t v = 0; v < frames_used_[f].views.size(); ++v) {
          if (!active_[f][v]) continue;
          const WandView& view = frames_used_[f].views[v];
          problem.AddResidualBlock(MarkerReprojectionError::Create(view.pixels[0]), loss.get(),
                                   poses[view.camera].data(), intrinsics[view.camera].data(), points_[f].data());
        }
      }
      for (size_t c = 0; c < n; ++c) {
        if (!problem.HasParameterBlock(poses[c].data())) continue;
        problem.SetParameterBlockConstant(intrinsics[c].data());
        if (c == reference_) problem.SetParameterBlockConstant(poses[c].data());
        if (c == first_joiner_) {
          // Its distance from the reference (|t|, the reference sitting at the origin) is the
          // unscaled solve's gauge.
          problem.SetManifold(poses[c].data(), new ceres::ProductManifold<ceres::EuclideanManifold<3>, ceres::SphereManifold<3>>(
                                                   ceres::EuclideanManifold<3>(), ceres::SphereManifold<3>()));
        }
      }
      ceres::Solver::Options solver;
      solver.linear_solver_type = ceres::SPARSE_SCHUR;
      solver.max_num_iterations = options_.max_iterations;
      solver.num_threads = options_.num_threads;
      solver.function_tolerance = 1e-12;
      solver.gradient_tolerance = 1e-14;
      solver.parameter_tolerance = 1e-12;
      solver.logging_type = ceres::SILENT;
      ceres::Solver::Summary summary;
      ceres::Solve(solver, &problem, &summary);
      for (size_t c = 0; c < n; ++c) SetPoseFromBlock(poses[c].data(), &rig_.cameras[c]);
      DropOutliers();
    }
  }

  // Residual lengths of every view under the current solve (1e9 where it does not project).
  std::vector<std::vector<double>> Residuals() const {
    std::vector<std::vector<double>> errors(frames_used_.size());
    for (size_t f = 0; f < frames_used_.size(); ++f) {
      errors[f].assign(frames_used_[f].views.size(), 1e9);
      if (!has_point_[f]) continue;
      const Eigen::Vector3d p(points_[f][0], points_[f][1], points_[f][2]);
      for (size_t v = 0; v < frames_used_[f].views.size(); ++v) {
        const WandView& view = frames_used_[f].views[v];
        Eigen::Vector2d projected;
        if (rig_.cameras[view.camera].ProjectToPixel(p, &projected)) errors[f][v] = (projected - view.pixels[0]).norm();
      }
    }
    return errors;
  }

  void DropOutliers() {
    const std::vector<std::vector<double>> errors = Residuals();
    std::vector<std::vector<double>> per_camera(rig_.cameras.size());
    for (size_t f = 0; f < frames_used_.size(); ++f) {
      for (size_t v = 0; v < errors[f].size(); ++v) {
        if (has_point_[f] && active_[f][v]) per_camera[frames_used_[f].views[v].camera].push_back(errors[f][v]);
      }
    }
    std::vector<double> gate(rig_.cameras.size());
    for (size_t c = 0; c < gate.size(); ++c) gate[c] = std::max(options_.outlier_px, 5.0 * 1.4826 * Median(per_camera[c]));
    for (size_t f = 0; f < frames_used_.size(); ++f) {
      for (size_t v = 0; v < errors[f].size(); ++v) {
        if (has_point_[f]) active_[f][v] = errors[f][v] <= gate[frames_used_[f].views[v].camera];
      }
    }
  }

  // Stage 4: the two-blob frames triangulated with the solved cameras; their median length is
  // the scale bar's.
  void Scale() {
    WandSelectionStats stats;
    const std::vector<WandFrame> bars =
        SelectWandFrames(frames_, rig_, WandGeometry::TwoMarker(options_.scale_length_mm), options_.selection, &stats);
    std::vector<double> lengths;
    for (const WandFrame& frame : bars) {
      // Which blob of each view is end 0. A pair of views whose epipolar lines run along the bar
      // cannot tell (both orders fit), so the order is not taken from the first view alone: the
      // views are oriented one at a time, each time the view whose orders differ most in Sampson
      // error summed over the views already oriented, and by that sum.
      const size_t n = frame.views.size();
      std::vector<char> oriented(n, 0), swapped(n, 0);
      oriented[0] = 1;
      for (size_t done = 1; done < n; ++done) {
        size_t best = 0;
        double best_margin = -1.0, best_difference = 0.0;
        for (size_t v = 0; v < n; ++v) {
          if (oriented[v]) continue;
          const WandView& view = frame.views[v];
          double difference = 0.0;  // straight minus swapped
          for (size_t o = 0; o < n; ++o) {
            if (!oriented[o]) continue;
            const WandView& other = frame.views[o];
            const Eigen::Vector2d& o0 = other.normalized[swapped[o] ? 1 : 0];
            const Eigen::Vector2d& o1 = other.normalized[swapped[o] ? 0 : 1];
            const Eigen::Matrix3d e = Essential(other.camera, view.camera);
            difference += Sampson(e, o0, view.normalized[0]) + Sampson(e, o1, view.normalized[1]) -
                          Sampson(e, o0, view.normalized[1]) - Sampson(e, o1, view.normalized[0]);
          }
          if (std::abs(difference) > best_margin) {
            best = v;
            best_margin = std::abs(difference);
            best_difference = difference;
          }
        }
        oriented[best] = 1;
        swapped[best] = best_difference > 0.0;
      }
      std::vector<PointView> ends[2];
      for (size_t v = 0; v < n; ++v) {
        const WandView& view = frame.views[v];
        ends[0].push_back({Projection(rig_.cameras[view.camera]), view.normalized[swapped[v] ? 1 : 0]});
        ends[1].push_back({Projection(rig_.cameras[view.camera]), view.normalized[swapped[v] ? 0 : 1]});
      }
      Eigen::Vector3d a, b;
      if (TriangulatePoint(ends[0], &a) && TriangulatePoint(ends[1], &b)) lengths.push_back((b - a).norm());
    }
    result_.scale_frames = lengths.size();
    if (lengths.size() < options_.min_scale_frames)
      throw std::runtime_error("only " + std::to_string(lengths.size()) +
                               " frames show the scale bar (exactly two blobs in two or more cameras; " +
                               std::to_string(options_.min_scale_frames) +
                               " needed); show the bar of known length to the cameras after the waving");
    const double scale = options_.scale_length_mm / Median(lengths);
    for (Camera& camera : rig_.cameras) camera.translation *= scale;
    for (auto& p : points_) {
      for (double& x : p) x *= scale;
    }
    double sum = 0.0;
    for (double l : lengths) sum += (l * scale - options_.scale_length_mm) * (l * scale - options_.scale_length_mm);
    result_.scale_length_rms_mm = std::sqrt(sum / static_cast<double>(lengths.size()));
  }

  // b_from_a's essential matrix under the solved poses.
  Eigen::Matrix3d Essential(size_t a, size_t b) const {
    const Camera& ca = rig_.cameras[a];
    const Camera& cb = rig_.cameras[b];
    const Eigen::Matrix3d r = cb.rotation * ca.rotation.transpose();
    const Eigen::Vector3d t = cb.translation - r * ca.translation;
    Eigen::Matrix3d skew;
    skew << 0.0, -t.z(), t.y(), t.z(), 0.0, -t.x(), -t.y(), t.x(), 0.0;
    return skew * r;
  }

  SingleMarkerResult Report() {
    result_.rig = rig_;
    result_.reference_id = rig_.cameras[reference_].id;
    const std::vector<std::vector<double>> errors = Residuals();
    std::vector<double> sum(rig_.cameras.size(), 0.0);
    result_.cameras.resize(rig_.cameras.size());
    for (size_t c = 0; c < rig_.cameras.size(); ++c) {
      result_.cameras[c].id = rig_.cameras[c].id;
      result_.cameras[c].views = views_[c];
      result_.cameras[c].joined_through = joined_through_[c];
    }
    for (size_t f = 0; f < frames_used_.size(); ++f) {
      if (!has_point_[f]) continue;
      ++result_.frames_used;
      for (size_t v = 0; v < errors[f].size(); ++v) {
        if (!active_[f][v]) continue;
        const size_t c = frames_used_[f].views[v].camera;
        ++result_.cameras[c].used;
        sum[c] += errors[f][v] * errors[f][v];
      }
    }
    for (size_t c = 0; c < rig_.cameras.size(); ++c) {
      if (result_.cameras[c].used > 0) result_.cameras[c].rms_px = std::sqrt(sum[c] / result_.cameras[c].used);
    }
    return result_;
  }

  const std::vector<FrameSet>& frames_;
  const SingleMarkerOptions& options_;
  Rig rig_;
  std::vector<char> posed_;
  std::vector<size_t> views_;
  std::vector<uint32_t> joined_through_;
  std::vector<WandFrame> frames_used_;
  std::vector<std::array<double, 3>> points_;
  std::vector<char> has_point_;
  std::vector<std::vector<char>> active_;
  size_t reference_ = 0;
  size_t first_joiner_ = 0;
  SingleMarkerResult result_;
};

}  // namespace

SingleMarkerResult CalibrateSingleMarker(const std::vector<FrameSet>& frames, const Rig& intrinsics,
                                         const SingleMarkerOptions& options) {
  options.Check();
  return SingleMarkerSolver(frames, intrinsics, options).Run();
}

}  // namespace mocap
