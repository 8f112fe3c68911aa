// Pairwise essential matrices (OpenCV five-point RANSAC on undistorted normalized points) and
// greedy chaining from the reference camera along the strongest covisibility links.
#include "calib/wand_initialization.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "geometry/triangulation.h"

namespace mocap {
namespace {

// Sampson distance (squared, normalized units) of a correspondence under essential matrix E.
double Sampson(const Eigen::Matrix3d& e, const Eigen::Vector2d& x1, const Eigen::Vector2d& x2) {
  const Eigen::Vector3d a(x1.x(), x1.y(), 1.0);
  const Eigen::Vector3d b(x2.x(), x2.y(), 1.0);
  const Eigen::Vector3d ea = e * a;
  const Eigen::Vector3d eb = e.transpose() * b;
  const double num = b.dot(ea);
  const double den = ea.x() * ea.x() + ea.y() * ea.y() + eb.x() * eb.x() + eb.y() * eb.y();
  return den > 0.0 ? num * num / den : 0.0;
}

double Median(std::vector<double> values) {
  const size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + static_cast<long>(mid), values.end());
  return values[mid];
}

}  // namespace

void WandInitializationOptions::Check() const {
  if (min_pair_frames < 8) throw std::invalid_argument("min_pair_frames must be >= 8");
  if (max_frames_per_pair < min_pair_frames) {
    throw std::invalid_argument("max_frames_per_pair must be >= min_pair_frames");
  }
  if (!(ransac_threshold_px > 0.0)) throw std::invalid_argument("ransac_threshold_px must be > 0");
  if (!(ransac_confidence > 0.0 && ransac_confidence < 1.0)) {
    throw std::invalid_argument("ransac_confidence must be in (0, 1)");
  }
  if (ransac_max_iterations < 10) throw std::invalid_argument("ransac_max_iterations must be >= 10");
  if (!(max_length_spread > 0.0)) throw std::invalid_argument("max_length_spread must be > 0");
}

bool EstimateWandRelativePose(const std::vector<std::pair<const WandView*, const WandView*>>& views,
                              const WandGeometry& wand, double focal_px,
                              const WandInitializationOptions& options, RelativePose* cam2_from_cam1,
                              std::string* why) {
  if (static_cast<int>(views.size()) < options.min_pair_frames) {
    *why = "only " + std::to_string(views.size()) + " shared wand frames (need " +
           std::to_string(options.min_pair_frames) + ")";
    return false;
  }
  // Both end pairings of every frame go in; the middle marker (if any) is always labelled.
  std::vector<cv::Point2d> points1, points2;
  for (const auto& [v1, v2] : views) {
    const auto& a = v1->normalized;
    const auto& b = v2->normalized;
    const size_t last = a.size() - 1;
    points1.insert(points1.end(), {{a[0].x(), a[0].y()}, {a[last].x(), a[last].y()},
                                   {a[0].x(), a[0].y()}, {a[last].x(), a[last].y()}});
    points2.insert(points2.end(), {{b[0].x(), b[0].y()}, {b[last].x(), b[last].y()},
                                   {b[last].x(), b[last].y()}, {b[0].x(), b[0].y()}});
    if (a.size() == 3) {
      points1.emplace_back(a[1].x(), a[1].y());
      points2.emplace_back(b[1].x(), b[1].y());
    }
  }
  const double threshold = options.ransac_threshold_px / focal_px;
  const cv::Mat identity = cv::Mat::eye(3, 3, CV_64F);
  cv::Mat mask;
  const cv::Mat e_cv = cv::findEssentialMat(points1, points2, identity, cv::RANSAC, options.ransac_confidence,
                                            threshold, options.ransac_max_iterations, mask);
  if (e_cv.rows != 3 || e_cv.cols != 3) {
    *why = "no essential matrix found";
    return false;
  }
  Eigen::Matrix3d e;
  cv::cv2eigen(e_cv, e);

  // Keep, per frame, the end pairing the essential matrix explains; drop frames where both
  // pairings fit (wand in the epipolar plane) or neither does.
  const double gate = threshold * threshold * 4.0;
  std::vector<cv::Point2d> chosen1, chosen2;
  std::vector<std::pair<const WandView*, bool>> kept;  // view of camera 1 frame, swapped in camera 2
  for (const auto& [v1, v2] : views) {
    const auto& a = v1->normalized;
    const auto& b = v2->normalized;
    const size_t last = a.size() - 1;
    const double straight = Sampson(e, a[0], b[0]) + Sampson(e, a[last], b[last]);
    const double swapped = Sampson(e, a[0], b[last]) + Sampson(e, a[last], b[0]);
    const bool swap = swapped < straight;
    const double best = std::min(straight, swapped);
    const double other = std::max(straight, swapped);
    if (best > gate || other < 4.0 * gate) continue;
    chosen1.emplace_back(a[0].x(), a[0].y());
    chosen2.emplace_back(swap ? b[last].x() : b[0].x(), swap ? b[last].y() : b[0].y());
    chosen1.emplace_back(a[last].x(), a[last].y());
    chosen2.emplace_back(swap ? b[0].x() : b[last].x(), swap ? b[0].y() : b[last].y());
    kept.emplace_back(v1, swap);
  }
  if (static_cast<int>(kept.size()) < options.min_pair_frames) {
    *why = "only " + std::to_string(kept.size()) + " frames agree with one epipolar geometry (need " +
           std::to_string(options.min_pair_frames) + ")";
    return false;
  }
  cv::Mat r_cv, t_cv, pose_mask;
  const int in_front = cv::recoverPose(e_cv, chosen1, chosen2, identity, r_cv, t_cv, pose_mask);
  if (in_front < options.min_pair_frames) {
    *why = "too few points in front of both cameras (" + std::to_string(in_front) + ")";
    return false;
  }
  Eigen::Matrix3d rotation;
  Eigen::Vector3d direction;
  cv::cv2eigen(r_cv, rotation);
  cv::cv2eigen(t_cv, direction);

  // Wand lengths in units of the (unit) baseline give the pair's metric scale.
  Eigen::Matrix<double, 3, 4> first = Eigen::Matrix<double, 3, 4>::Zero();
  first.leftCols<3>().setIdentity();
  Eigen::Matrix<double, 3, 4> second;
  second.leftCols<3>() = rotation;
  second.col(3) = direction;
  std::vector<double> lengths;
  for (size_t k = 0; k < kept.size(); ++k) {
    if (pose_mask.at<uchar>(static_cast<int>(2 * k)) == 0 || pose_mask.at<uchar>(static_cast<int>(2 * k + 1)) == 0) {
      continue;
    }
    Eigen::Vector3d ends[2];
    bool ok = true;
    for (int m = 0; m < 2 && ok; ++m) {
      const cv::Point2d& p1 = chosen1[2 * k + m];
      const cv::Point2d& p2 = chosen2[2 * k + m];
      ok = TriangulatePoint({{first, Eigen::Vector2d(p1.x, p1.y)}, {second, Eigen::Vector2d(p2.x, p2.y)}},
                             &ends[m]) &&
           ends[m].z() > 0.0;
    }
    if (ok) lengths.push_back((ends[1] - ends[0]).norm());
  }
  if (static_cast<int>(lengths.size()) < options.min_pair_frames) {
    *why = "too few wand frames triangulate in front of both cameras (" + std::to_string(lengths.size()) + ")";
    return false;
  }
  const double median = Median(lengths);
  std::vector<double> deviations;
  for (double l : lengths) deviations.push_back(std::abs(l - median));
  const double spread = Median(deviations) / median;
  if (!(median > 0.0) || spread > options.max_length_spread) {
    *why = "triangulated wand lengths disagree (spread " + std::to_string(spread * 100.0) + " %)";
    return false;
  }
  cam2_from_cam1->rotation = rotation;
  cam2_from_cam1->translation = direction * (wand.LengthMm() / median);
  cam2_from_cam1->inlier_frames = static_cast<int>(lengths.size());
  cam2_from_cam1->length_spread = spread;
  return true;
}

WandInitialization InitializeWandPoses(const std::vector<WandFrame>& frames, const Rig& rig,
                                       const WandGeometry& wand, const WandInitializationOptions& options) {
  wand.Check();
  options.Check();
  const size_t n = rig.cameras.size();
  WandInitialization init;
  init.cameras = rig.cameras;
  init.posed.assign(n, false);
  init.unposed_reason.assign(n, "");
  init.views_per_camera.assign(n, 0);
  if (n < 2) throw std::runtime_error("a wand calibration needs at least two cameras");

  // Covisibility: frame indices each camera pair shares.
  std::map<std::pair<size_t, size_t>, std::vector<size_t>> shared;
  for (size_t f = 0; f < frames.size(); ++f) {
    const auto& views = frames[f].views;
    for (size_t i = 0; i < views.size(); ++i) {
      ++init.views_per_camera[views[i].camera];
      for (size_t j = 0; j < views.size(); ++j) {
        if (i != j) shared[{views[i].camera, views[j].camera}].push_back(f);
      }
    }
  }
  if (options.reference_camera >= 0) {
    if (static_cast<size_t>(options.reference_camera) >= n) {
      throw std::invalid_argument("reference camera index out of range");
    }
    init.reference_camera = static_cast<size_t>(options.reference_camera);
  } else {
    init.reference_camera = static_cast<size_t>(
        std::max_element(init.views_per_camera.begin(), init.views_per_camera.end()) -
        init.views_per_camera.begin());
  }
  const size_t ref = init.reference_camera;
  init.cameras[ref].rotation.setIdentity();
  init.cameras[ref].translation.setZero();
  init.posed[ref] = true;

  auto view_of = [&](size_t frame, size_t camera) -> const WandView* {
    for (const WandView& view : frames[frame].views) {
      if (view.camera == camera) return &view;
    }
    return nullptr;
  };

  std::set<std::pair<size_t, size_t>> failed;
  std::vector<std::string> last_failure(n);
  for (;;) {
    // Strongest untried link from the posed set to an unposed camera.
    size_t best_count = 0, parent = 0, child = 0;
    for (size_t p = 0; p < n; ++p) {
      if (!init.posed[p]) continue;
      for (size_t c = 0; c < n; ++c) {
        if (init.posed[c] || failed.count({p, c}) != 0) continue;
        const auto it = shared.find({p, c});
        const size_t count = it == shared.end() ? 0 : it->second.size();
        if (count > best_count) {
          best_count = count;
          parent = p;
          child = c;
        }
      }
    }
    if (best_count == 0) break;
    const std::vector<size_t>& common = shared.at({parent, child});
    std::vector<std::pair<const WandView*, const WandView*>> pairs;
    const size_t step = std::max<size_t>(1, common.size() / static_cast<size_t>(options.max_frames_per_pair));
    for (size_t k = 0; k < common.size(); k += step) {
      pairs.emplace_back(view_of(common[k], parent), view_of(common[k], child));
    }
    const double focal = 0.25 * (rig.cameras[parent].intrinsics.fx + rig.cameras[parent].intrinsics.fy +
                                 rig.cameras[child].intrinsics.fx + rig.cameras[child].intrinsics.fy);
    RelativePose relative;
    std::string why;
    if (!EstimateWandRelativePose(pairs, wand, focal, options, &relative, &why)) {
      failed.insert({parent, child});
      last_failure[child] = "with camera " + std::to_string(rig.cameras[parent].id) + ": " + why;
      continue;
    }
    Camera& c = init.cameras[child];
    const Camera& p = init.cameras[parent];
    c.rotation = relative.rotation * p.rotation;
    c.translation = relative.rotation * p.translation + relative.translation;
    init.posed[child] = true;
  }
  for (size_t i = 0; i < n; ++i) {
    if (init.posed[i]) continue;
    init.unposed_reason[i] = last_failure[i].empty()
                                 ? "shares no wand frames with a calibrated camera"
                                 : "no usable relative pose (" + last_failure[i] + ")";
  }
  size_t posed = 0;
  for (bool p : init.posed) posed += p ? 1 : 0;
  if (posed < 2) {
    throw std::runtime_error("no camera pair could be initialised from the wand frames (reference camera " +
                             std::to_string(rig.cameras[ref].id) +
                             "): wave the wand where at least two cameras see it at once");
  }
  return init;
}

}  // namespace mocap
