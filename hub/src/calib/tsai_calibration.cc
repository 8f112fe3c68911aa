// Tsai's calibration (seed 000 section 3.2): the linear stages per view (tsai_linear.cc), then
// the joint Ceres refinement of every parameter with kappa1 in image pixels, and whether the
// points determine kappa1 (the fit's covariance).
#include "calib/tsai_calibration.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/Dense>

#include "calib/tsai_linear.h"

namespace mocap {

void TsaiCalibrationOptions::Check() const {
  if (width <= 0 || height <= 0 || width > (1 << 20) || height > (1 << 20))
    throw std::invalid_argument("the image size (--width, --height) must be 1..1048576 px");
  if (!(pixel_mm > 0.0 && pixel_mm < 1.0)) throw std::invalid_argument("pixel_mm must be within (0, 1) mm");
  if (!(sx > 0.5 && sx < 2.0)) throw std::invalid_argument("sx must be within (0.5, 2)");
  if (max_iterations < 1) throw std::invalid_argument("max_iterations must be >= 1");
  if (!(huber_px > 0.0)) throw std::invalid_argument("huber_px must be > 0");
  if (!(max_rms_px > 0.0)) throw std::invalid_argument("max_rms_px must be > 0");
  if (!(max_kappa1_corner_sigma_px > 0.0)) throw std::invalid_argument("max_kappa1_corner_sigma_px must be > 0");
}

namespace {

// Newton steps inverting Tsai's distortion per point: ample for |kappa1 r^2| up to ~0.3.
constexpr int kNewtonSteps = 8;

// The reprojection error in the image (px) through Tsai's exact model: the undistorted sensor
// point from the pose and f, its distorted radius (ru = rd (1 + kappa1 rd^2) solved for
// rd = d ru), then the frame buffer through sx and the image centre.
struct TsaiPixelError {
  TsaiPixelError(const Eigen::Vector3d& point, const Eigen::Vector2d& pixel, double dpx, double dpy)
      : point_(point), pixel_(pixel), dpx_(dpx), dpy_(dpy) {}

  template <typename T>
  bool operator()(const T* pose, const T* f, const T* kappa1, const T* centre, const T* sx, T* residuals) const {
    const T world[3] = {T(point_.x()), T(point_.y()), T(point_.z())};
    T cam[3];
    ceres::AngleAxisRotatePoint(pose, world, cam);
    for (int i = 0; i < 3; ++i) cam[i] += pose[3 + i];
    const T xu = f[0] * cam[0] / cam[2];
    const T yu = f[0] * cam[1] / cam[2];
    const T kr = kappa1[0] * (xu * xu + yu * yu);
    T d(1.0);
    for (int i = 0; i < kNewtonSteps; ++i) d -= (d * (T(1.0) + kr * d * d) - T(1.0)) / (T(1.0) + T(3.0) * kr * d * d);
    residuals[0] = sx[0] * xu * d / T(dpx_) + centre[0] - T(pixel_.x());
    residuals[1] = yu * d / T(dpy_) + centre[1] - T(pixel_.y());
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Vector3d& point, const Eigen::Vector2d& pixel, double dpx,
                                     double dpy) {
    return new ceres::AutoDiffCostFunction<TsaiPixelError, 2, 6, 1, 1, 2, 1>(
        new TsaiPixelError(point, pixel, dpx, dpy));
  }

  Eigen::Vector3d point_;
  Eigen::Vector2d pixel_;
  double dpx_, dpy_;
};

std::array<double, 6> PoseOf(const TsaiCamera& camera) {
  const Eigen::Matrix3d rotation = camera.Rotation();
  std::array<double, 6> pose{};
  ceres::RotationMatrixToAngleAxis(ceres::ColumnMajorAdapter3x3(rotation.data()), pose.data());
  pose[3] = camera.tx;
  pose[4] = camera.ty;
  pose[5] = camera.tz;
  return pose;
}

double Rms(const std::vector<std::vector<ControlPoint>>& views, const std::vector<TsaiCamera>& cameras) {
  double sum = 0.0;
  size_t count = 0;
  for (size_t v = 0; v < views.size(); ++v) {
    for (const ControlPoint& p : views[v]) {
      Eigen::Vector2d projected;
      if (!cameras[v].Project(p.point_in_world, &projected)) return std::numeric_limits<double>::infinity();
      sum += (projected - p.pixel).squaredNorm();
      ++count;
    }
  }
  return std::sqrt(sum / static_cast<double>(count));
}

// The joint refinement; fills result->views and kappa1's standard deviation.
class TsaiRefinement {
 public:
  TsaiRefinement(const std::vector<std::vector<ControlPoint>>& views, const std::vector<TsaiLinearView>& linear,
                 const TsaiCalibrationOptions& options)
      : views_(views), linear_(linear), options_(options) {}

  void Run(TsaiCalibrationResult* result) {
    bool coplanar = true;
    std::vector<double> focal;
    for (const TsaiLinearView& v : linear_) {
      coplanar = coplanar && v.coplanar;
      focal.push_back(v.camera.f);
    }
    std::nth_element(focal.begin(), focal.begin() + static_cast<std::ptrdiff_t>(focal.size() / 2), focal.end());
    const TsaiCamera& first = linear_[0].camera;
    double f = focal[focal.size() / 2], kappa1 = 0.0, sx = options_.sx;
    for (const TsaiLinearView& v : linear_) {
      if (!v.coplanar) {
        sx = v.camera.sx;
        break;
      }
    }
    std::array<double, 2> centre = {first.cx, first.cy};
    std::vector<std::array<double, 6>> poses;
    for (const TsaiLinearView& v : linear_) poses.push_back(PoseOf(v.camera));
    ceres::Problem problem;
    size_t residuals = 0;
    for (size_t v = 0; v < views_.size(); ++v) {
      for (const ControlPoint& p : views_[v]) {
        problem.AddResidualBlock(TsaiPixelError::Create(p.point_in_world, p.pixel, first.dpx, first.dpy),
                                 new ceres::HuberLoss(options_.huber_px), poses[v].data(), &f, &kappa1, centre.data(),
                                 &sx);
        residuals += 2;
      }
    }
    if (coplanar) problem.SetParameterBlockConstant(&sx);
    if (!options_.refine_centre) problem.SetParameterBlockConstant(centre.data());
    ceres::Solver::Options solver;
    // The poses are independent given the shared intrinsics: eliminated first (Schur).
    auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
    for (std::array<double, 6>& pose : poses) ordering->AddElementToGroup(pose.data(), 0);
    for (double* block : {&f, &kappa1, centre.data(), &sx}) ordering->AddElementToGroup(block, 1);
    solver.linear_solver_type = ceres::DENSE_SCHUR;
    solver.linear_solver_ordering = ordering;
    solver.max_num_iterations = options_.max_iterations;
    solver.function_tolerance = 1e-14;
    solver.gradient_tolerance = 1e-16;
    solver.parameter_tolerance = 1e-14;
    solver.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    ceres::Solve(solver, &problem, &summary);
    if (!(f > 0.0) || !std::isfinite(f) || !std::isfinite(kappa1))
      throw std::invalid_argument("the non-linear refinement diverged (f " + std::to_string(f) +
                                  "): use more control points spread over the image");
    result->views.clear();
    for (size_t v = 0; v < views_.size(); ++v) {
      TsaiCamera camera = first;
      Eigen::Matrix3d rotation;
      ceres::AngleAxisToRotationMatrix(poses[v].data(), ceres::ColumnMajorAdapter3x3(rotation.data()));
      camera.SetRotation(rotation);
      camera.tx = poses[v][3];
      camera.ty = poses[v][4];
      camera.tz = poses[v][5];
      camera.f = f;
      camera.kappa1 = kappa1;
      camera.cx = centre[0];
      camera.cy = centre[1];
      camera.sx = sx;
      result->views.push_back(camera);
    }
    const size_t unknowns = static_cast<size_t>(problem.NumParameters()) - (coplanar ? 1 : 0) -
                        (options_.refine_centre ? 0 : 2);
    result->kappa1_sigma = Kappa1Sigma(&problem, &kappa1, summary.final_cost, residuals, unknowns);
  }

 private:
  // kappa1's standard deviation: its covariance block at unit pixel noise, scaled by the
  // residuals' variance; infinite when the fit leaves it unconstrained.
  static double Kappa1Sigma(ceres::Problem* problem, const double* kappa1, double cost, size_t residuals,
                            size_t unknowns) {
    if (residuals <= unknowns) return std::numeric_limits<double>::infinity();
    ceres::Covariance::Options covariance_options;
    covariance_options.algorithm_type = ceres::SPARSE_QR;
    ceres::Covariance covariance(covariance_options);
    const std::vector<std::pair<const double*, const double*>> blocks = {{kappa1, kappa1}};
    double variance = 0.0;
    if (!covariance.Compute(blocks, problem) || !covariance.GetCovarianceBlock(kappa1, kappa1, &variance))
      return std::numeric_limits<double>::infinity();
    const double noise = 2.0 * cost / static_cast<double>(residuals - unknowns);
    return std::sqrt(std::max(0.0, variance * noise));
  }

  const std::vector<std::vector<ControlPoint>>& views_;
  const std::vector<TsaiLinearView>& linear_;
  const TsaiCalibrationOptions& options_;
};

// Whether kappa1 is pinned: its standard deviation as the displacement at the image corner
// farthest from the centre, and how far the points reach towards that corner.
void JudgeKappa1(const std::vector<std::vector<ControlPoint>>& views, const TsaiCalibrationOptions& options,
                 TsaiCalibrationResult* result) {
  const TsaiCamera& t = result->tsai;
  const auto sensor = [&t](const Eigen::Vector2d& pixel) {
    return Eigen::Vector2d(t.dpx * (pixel.x() - t.cx) / t.sx, t.dpy * (pixel.y() - t.cy));
  };
  const double corner = sensor(Eigen::Vector2d(t.cx < 0.5 * options.width ? options.width : 0.0,
                                               t.cy < 0.5 * options.height ? options.height : 0.0))
                            .norm();
  double reach = 0.0;
  for (const std::vector<ControlPoint>& view : views) {
    for (const ControlPoint& p : view) reach = std::max(reach, sensor(p.pixel).norm());
  }
  result->coverage = reach / corner;
  result->kappa1_corner_sigma_px = result->kappa1_sigma * corner * corner * corner / std::min(t.dpx, t.dpy);
  result->kappa1_determined = result->kappa1_corner_sigma_px <= options.max_kappa1_corner_sigma_px;
  if (result->kappa1_determined) return;
  char note[320];
  std::snprintf(note, sizeof(note),
                "kappa1 is undetermined: one standard deviation of it moves the image corner by %.2g px (at most "
                "%.2g px); the points reach %.0f %% of the way from the image centre to its corner: fill the "
                "image with the target, or add views that reach the corners",
                result->kappa1_corner_sigma_px, options.max_kappa1_corner_sigma_px, 100.0 * result->coverage);
  result->kappa1_note = note;
}

}  // namespace

TsaiCalibrationResult CalibrateTsaiViews(const std::vector<std::vector<ControlPoint>>& views,
                                         const TsaiCalibrationOptions& options) {
  options.Check();
  if (views.empty()) throw std::invalid_argument("Tsai's method needs at least one view of control points");
  std::vector<TsaiLinearView> linear;
  TsaiCalibrationResult result;
  result.coplanar = true;
  for (size_t v = 0; v < views.size(); ++v) {
    const std::string which = views.size() > 1 ? "view " + std::to_string(v + 1) + ": " : "";
    for (const ControlPoint& p : views[v]) {
      if (!p.point_in_world.allFinite() || !p.pixel.allFinite())
        throw std::invalid_argument(which + "a control point is not finite");
    }
    if (views[v].size() < 5)
      throw std::invalid_argument(which + "Tsai's method needs at least 5 coplanar or 7 control points, got " +
                                  std::to_string(views[v].size()));
    try {
      linear.push_back(TsaiLinearStage(views[v], options));
    } catch (const std::invalid_argument& error) {
      throw std::invalid_argument(which + error.what());
    }
    result.coplanar = result.coplanar && linear.back().coplanar;
  }
  std::vector<TsaiCamera> linear_cameras;
  for (const TsaiLinearView& v : linear) linear_cameras.push_back(v.camera);
  result.linear = linear_cameras[0];
  result.linear_rms_px = Rms(views, linear_cameras);
  if (options.refine) {
    TsaiRefinement(views, linear, options).Run(&result);
  } else {
    result.views = linear_cameras;
    result.kappa1_sigma = std::numeric_limits<double>::infinity();
  }
  result.tsai = result.views[0];
  result.rms_px = Rms(views, result.views);
  if (!(result.rms_px <= options.max_rms_px))
    throw std::invalid_argument("the control points do not fit one camera (reprojection RMS " +
                                std::to_string(result.rms_px) + " px, at most " + std::to_string(options.max_rms_px) +
                                " px): check that each x y z is paired with its own u v");
  JudgeKappa1(views, options, &result);
  if (!options.refine) result.kappa1_note = "kappa1 is not estimated without the non-linear stage";
  if (!result.kappa1_determined && options.require_kappa1) throw std::invalid_argument(result.kappa1_note);
  result.camera = CameraFromTsai(result.tsai, options.camera_id, options.width, options.height);
  return result;
}

TsaiCalibrationResult CalibrateTsai(const std::vector<ControlPoint>& points, const TsaiCalibrationOptions& options) {
  return CalibrateTsaiViews({points}, options);
}

}  // namespace mocap
