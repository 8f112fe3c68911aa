// Tsai's method on seed 000's target layout (3 x 5 squares of 20 mm per face), folded
// (non-coplanar) and one face alone (coplanar), seen by simulated Tsai cameras with radial
// distortion; intrinsics, lens and views drawn at random per seed. The views follow seed 000's
// protocol (section 3.4): the camera close enough that the target fills the image (the points
// spread over the whole image, for kappa1 and the image centre) and the nearest-to-farthest
// depth of the points about the camera's distance; one face viewed at >= 30 degrees, several
// views of it for the intrinsics. Asserted: exact from noiseless points; at 0.2 px the centre
// within 1 mm and kappa1 within 2 % of the truth on every draw, kappa1 reported determined; a
// distant target (points a third of the way to the corners) reports kappa1 undetermined with a
// standard deviation that covers its error; the DLT of the same points agrees on the centre;
// bad point sets are refused with the reason.
#include "calib/tsai_calibration.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "calib/calibration_target.h"
#include "calib/dlt.h"
#include "simcore/test_scenes.h"

namespace mocap {
namespace {

constexpr int kWidth = 1280;
constexpr int kHeight = 800;
constexpr double kPixelMm = 0.005;
constexpr double kNoisePx = 0.2;
constexpr int kDraws = 20;
constexpr int kFoldedViews = 40;  // views per draw where the intrinsics come from several views
constexpr int kFaceViews = 40;
constexpr double kPi = 3.14159265358979323846;

// A random lens: focal length 900-1300 px, the image centre up to 20 px off the middle, kappa1
// moving the image corner by 2-5 % of its radius, barrel or pincushion, sx within 2 % of 1
// (1 for coplanar targets: their points cannot give it).
TsaiCamera RandomLens(std::mt19937* rng, bool with_sx) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  TsaiCamera t;
  t.ncx = t.nfx = kWidth;
  t.dx = t.dy = t.dpx = t.dpy = kPixelMm;
  t.f = (900.0 + 400.0 * unit(*rng)) * kPixelMm;
  t.cx = 0.5 * kWidth + 40.0 * (unit(*rng) - 0.5);
  t.cy = 0.5 * kHeight + 40.0 * (unit(*rng) - 0.5);
  t.sx = with_sx ? 0.98 + 0.04 * unit(*rng) : 1.0;
  const double corner_mm = kPixelMm * std::hypot(0.5 * kWidth, 0.5 * kHeight);
  const double fraction = (0.02 + 0.03 * unit(*rng)) * (unit(*rng) < 0.5 ? -1.0 : 1.0);
  t.kappa1 = fraction / (corner_mm * corner_mm);
  return t;
}

// The lens placed at `centre` looking at `target`, turned by `roll` about its axis.
TsaiCamera Place(TsaiCamera t, const Eigen::Vector3d& centre, const Eigen::Vector3d& target, double roll) {
  const Camera look = testing::LookAtCamera(1, centre, target);
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ()).toRotationMatrix() * look.rotation;
  t.SetRotation(rotation);
  const Eigen::Vector3d translation = -rotation * centre;
  t.tx = translation.x();
  t.ty = translation.y();
  t.tz = translation.z();
  return t;
}

Eigen::Vector3d Centre(const TsaiCamera& t) { return -t.Rotation().transpose() * Eigen::Vector3d(t.tx, t.ty, t.tz); }

// The target's points (both faces, or the floor face z = 0 alone) as the camera sees them,
// those inside the image, with Gaussian pixel noise.
std::vector<ControlPoint> Observe(const TsaiCamera& camera, bool both_faces, double noise_px, std::mt19937* rng) {
  const CalibrationTargetLayout layout;
  std::normal_distribution<double> noise(0.0, noise_px);
  std::vector<ControlPoint> points;
  const int first = both_faces ? 0 : layout.PointsPerFace();
  for (int i = first; i < layout.NumPoints(); ++i) {
    ControlPoint p;
    p.point_in_world = layout.PointInWorld(i);
    if (!camera.Project(p.point_in_world, &p.pixel)) continue;
    if (p.pixel.x() < 0 || p.pixel.y() < 0 || p.pixel.x() > kWidth || p.pixel.y() > kHeight) continue;
    if (noise_px > 0.0) p.pixel += Eigen::Vector2d(noise(*rng), noise(*rng));
    points.push_back(p);
  }
  return points;
}

// Seed 000's protocol for the folded target: from the front, between the floor and the wall
// (elevation 30-60 degrees, azimuth within 35 degrees), the page's width spanning 80-100 % of the
// image width, aimed within 10 mm of the target's middle, rolled up to 20 degrees.
TsaiCamera FoldedView(const TsaiCamera& lens, std::mt19937* rng) {
  const CalibrationTargetLayout layout;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double elevation = (30.0 + 30.0 * unit(*rng)) * kPi / 180.0;
  const double azimuth = (70.0 * unit(*rng) - 35.0) * kPi / 180.0;
  const Eigen::Vector3d direction(std::sin(azimuth), std::cos(azimuth) * std::cos(elevation),
                                  std::cos(azimuth) * std::sin(elevation));
  const double h = layout.HalfHeightMm();
  const Eigen::Vector3d middle(0.5 * layout.PageWidthMm(), 0.5 * h, 0.5 * h);
  const double span = 0.8 + 0.2 * unit(*rng);
  const double distance = lens.f / kPixelMm * layout.PageWidthMm() / (span * kWidth);
  const Eigen::Vector3d aim = middle + Eigen::Vector3d(20.0 * unit(*rng) - 10.0, 20.0 * unit(*rng) - 10.0, 0.0);
  return Place(lens, middle + distance * direction, aim, (40.0 * unit(*rng) - 20.0) * kPi / 180.0);
}

// One face (the floor, z = 0) at 30-50 degrees from its normal (seed 000: at least 30) from any
// side, filling 80-100 % of the image, rolled up to 20 degrees.
TsaiCamera FaceView(const TsaiCamera& lens, std::mt19937* rng) {
  const CalibrationTargetLayout layout;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double tilt = (30.0 + 20.0 * unit(*rng)) * kPi / 180.0;
  const double azimuth = 2.0 * kPi * unit(*rng);
  const Eigen::Vector3d direction(std::sin(tilt) * std::cos(azimuth), std::sin(tilt) * std::sin(azimuth),
                                  std::cos(tilt));
  const Eigen::Vector3d middle(0.5 * layout.PageWidthMm(), 0.5 * layout.HalfHeightMm(), 0.0);
  const double span = 0.8 + 0.2 * unit(*rng);
  const double distance = lens.f / kPixelMm * layout.HalfHeightMm() / (span * kHeight);
  return Place(lens, middle + distance * direction, middle, (40.0 * unit(*rng) - 20.0) * kPi / 180.0);
}

TsaiCalibrationOptions Options() {
  TsaiCalibrationOptions options;
  options.width = kWidth;
  options.height = kHeight;
  options.pixel_mm = kPixelMm;
  return options;
}

struct Spread {
  std::vector<double> centre_mm, kappa_percent, corner_sigma_px;
  void Add(const TsaiCalibrationResult& result, const TsaiCamera& truth) {
    centre_mm.push_back((Centre(result.tsai) - Centre(truth)).norm());
    kappa_percent.push_back(std::abs(100.0 * (result.tsai.kappa1 - truth.kappa1) / truth.kappa1));
    corner_sigma_px.push_back(result.kappa1_corner_sigma_px);
  }
  static double Median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  }
  static double Max(const std::vector<double>& v) { return *std::max_element(v.begin(), v.end()); }
  void Print(const char* name) const {
    std::printf("%s, %zu draws: centre median %.3f mm, worst %.3f mm; |kappa1 error| median %.2f %%, worst %.2f %%; "
                "kappa1 sigma at the corner median %.3f px, worst %.3f px\n",
                name, centre_mm.size(), Median(centre_mm), Max(centre_mm), Median(kappa_percent), Max(kappa_percent),
                Median(corner_sigma_px), Max(corner_sigma_px));
  }
};

TEST(TsaiCalibrationTest, NoiselessPointsGiveTheCameraExactly) {
  for (bool both_faces : {true, false}) {
    std::mt19937 rng(1);
    const TsaiCamera lens = RandomLens(&rng, both_faces);
    const TsaiCamera truth = both_faces ? FoldedView(lens, &rng) : FaceView(lens, &rng);
    const std::vector<ControlPoint> points = Observe(truth, both_faces, 0.0, &rng);
    ASSERT_GE(points.size(), both_faces ? 60u : 40u);
    const TsaiCalibrationResult result = CalibrateTsai(points, Options());
    SCOPED_TRACE(both_faces ? "folded target" : "one face");
    EXPECT_EQ(result.coplanar, !both_faces);
    EXPECT_LT(result.rms_px, 1e-6);
    EXPECT_LT((Centre(result.tsai) - Centre(truth)).norm(), 1e-4);
    EXPECT_NEAR(result.tsai.kappa1, truth.kappa1, 1e-8);
    EXPECT_NEAR(result.tsai.f, truth.f, 1e-7);
    EXPECT_NEAR(result.tsai.sx, truth.sx, 1e-8);
    EXPECT_NEAR(result.tsai.cx, truth.cx, 1e-4);
    // The linear stage alone is already close: the refinement has the lens and centre to add.
    EXPECT_LT((Centre(result.linear) - Centre(truth)).norm(), 25.0);
  }
}

// Several views per draw of one camera (its intrinsics shared, a pose per view), each view's
// centre within 1 mm and kappa1 within 2 %, kappa1 reported determined.
void SeveralViews(bool both_faces, int count, uint32_t seed, const char* name) {
  Spread spread;
  for (int draw = 0; draw < kDraws; ++draw) {
    std::mt19937 rng(seed + static_cast<uint32_t>(draw));
    const TsaiCamera lens = RandomLens(&rng, both_faces);
    std::vector<std::vector<ControlPoint>> views;
    std::vector<TsaiCamera> truths;
    for (int v = 0; v < count; ++v) {
      truths.push_back(both_faces ? FoldedView(lens, &rng) : FaceView(lens, &rng));
      views.push_back(Observe(truths.back(), both_faces, kNoisePx, &rng));
    }
    const TsaiCalibrationResult result = CalibrateTsaiViews(views, Options());
    spread.Add(result, truths[0]);
    SCOPED_TRACE(std::string(name) + ", draw " + std::to_string(draw));
    EXPECT_EQ(result.coplanar, !both_faces);
    EXPECT_LT(result.rms_px, 0.35);
    EXPECT_NEAR(result.tsai.sx, truths[0].sx, 1e-3);
    EXPECT_LT(std::abs(result.tsai.cx - truths[0].cx), 2.0);
    ASSERT_EQ(result.views.size(), static_cast<size_t>(count));
    for (int v = 0; v < count; ++v) EXPECT_LT((Centre(result.views[v]) - Centre(truths[v])).norm(), 1.0) << "view " << v;
    EXPECT_LT(spread.kappa_percent.back(), 2.0);
    EXPECT_TRUE(result.kappa1_determined) << result.kappa1_note;
    EXPECT_LT((result.camera.camera.CenterInWorld() - Centre(result.tsai)).norm(), 0.05);
  }
  spread.Print(name);
}

TEST(TsaiCalibrationTest, FoldedTargetFromSeveralViewsGivesCentreAndKappa1) {
  SeveralViews(true, kFoldedViews, 100, "seed target folded, several views");
}

TEST(TsaiCalibrationTest, OneFaceFromSeveralViewsGivesCentreAndKappa1) {
  SeveralViews(false, kFaceViews, 200, "seed target one face, several views");
}

// The folded target, one view per draw (seed 000's own protocol): the centre within 1 mm, and
// the DLT (with its lens terms) agrees on it; kappa1 is held to 2 % where it is reported
// determined, and its stated standard deviation covers the error where it is not.
TEST(TsaiCalibrationTest, FoldedTargetFromOneViewReportsWhatItDetermines) {
  Spread spread;
  int determined = 0;
  for (int draw = 0; draw < kDraws; ++draw) {
    std::mt19937 rng(100 + draw);
    const TsaiCamera truth = FoldedView(RandomLens(&rng, true), &rng);
    const std::vector<ControlPoint> points = Observe(truth, true, kNoisePx, &rng);
    const TsaiCalibrationResult result = CalibrateTsai(points, Options());
    spread.Add(result, truth);
    SCOPED_TRACE("draw " + std::to_string(draw) + ", " + std::to_string(points.size()) + " points");
    EXPECT_LT(result.rms_px, 0.35);
    EXPECT_LT(spread.centre_mm.back(), 1.0);
    EXPECT_LT(std::abs(result.tsai.kappa1 - truth.kappa1), 4.0 * result.kappa1_sigma);
    if (result.kappa1_determined) {
      ++determined;
      EXPECT_LT(spread.kappa_percent.back(), 2.0);
    }
    DltOptions dlt;
    dlt.width = kWidth;
    dlt.height = kHeight;
    dlt.refine_distortion = true;
    EXPECT_LT((CalibrateDlt(points, dlt).camera.CenterInWorld() - Centre(result.tsai)).norm(), 1.0);
  }
  spread.Print("seed target folded, one view");
  std::printf("  kappa1 reported determined in %d of %d draws\n", determined, kDraws);
}

// One face, one view per draw: Tsai's single coplanar view. kappa1 is held to 2 % where it is
// reported determined, and its stated standard deviation covers the error where it is not.
TEST(TsaiCalibrationTest, OneFaceFromOneViewReportsWhatItDetermines) {
  Spread spread;
  int determined = 0;
  for (int draw = 0; draw < kDraws; ++draw) {
    std::mt19937 rng(300 + draw);
    const TsaiCamera truth = FaceView(RandomLens(&rng, false), &rng);
    const TsaiCalibrationResult result = CalibrateTsai(Observe(truth, false, kNoisePx, &rng), Options());
    spread.Add(result, truth);
    SCOPED_TRACE("draw " + std::to_string(draw));
    const double error = std::abs(result.tsai.kappa1 - truth.kappa1);
    EXPECT_LT(error, 4.0 * result.kappa1_sigma);
    if (result.kappa1_determined) {
      ++determined;
      EXPECT_LT(spread.kappa_percent.back(), 2.0);
    }
  }
  spread.Print("seed target one face, one view");
  std::printf("  kappa1 reported determined in %d of %d draws\n", determined, kDraws);
}

// The target far off (its points reach about a third of the way to the image corners): kappa1 is reported undetermined with the reason, its stated
// standard deviation covering the error; require_kappa1 refuses such a set.
TEST(TsaiCalibrationTest, DistantTargetLeavesKappa1Undetermined) {
  Spread spread;
  for (int draw = 0; draw < kDraws; ++draw) {
    std::mt19937 rng(400 + draw);
    const TsaiCamera lens = RandomLens(&rng, true);
    TsaiCamera near = FoldedView(lens, &rng);
    const Eigen::Vector3d middle(95.0, 57.0, 57.0);
    const TsaiCamera truth = Place(lens, middle + 2.5 * (Centre(near) - middle), middle, 0.0);
    const std::vector<ControlPoint> points = Observe(truth, true, kNoisePx, &rng);
    const TsaiCalibrationResult result = CalibrateTsai(points, Options());
    spread.Add(result, truth);
    SCOPED_TRACE("draw " + std::to_string(draw));
    EXPECT_LT(result.coverage, 0.6);
    EXPECT_FALSE(result.kappa1_determined);
    EXPECT_NE(result.kappa1_note.find("fill the image"), std::string::npos) << result.kappa1_note;
    EXPECT_LT(std::abs(result.tsai.kappa1 - truth.kappa1), 4.0 * result.kappa1_sigma);
    TsaiCalibrationOptions strict = Options();
    strict.require_kappa1 = true;
    EXPECT_THROW(CalibrateTsai(points, strict), std::invalid_argument);
  }
  spread.Print("seed target folded, 2.5 times farther");
}

TEST(TsaiCalibrationTest, UnusablePointSetsAreRefused) {
  std::mt19937 rng(2);
  const TsaiCamera truth = FoldedView(RandomLens(&rng, true), &rng);
  std::vector<ControlPoint> points = Observe(truth, true, 0.0, &rng);
  EXPECT_THROW(CalibrateTsai({points.begin(), points.begin() + 4}, Options()), std::invalid_argument);
  EXPECT_THROW(CalibrateTsaiViews({}, Options()), std::invalid_argument);
  std::vector<ControlPoint> line;
  for (int i = 0; i < 10; ++i) {
    ControlPoint p;
    p.point_in_world = Eigen::Vector3d(10.0 * i, 0.0, 0.0);
    truth.Project(p.point_in_world, &p.pixel);
    line.push_back(p);
  }
  EXPECT_THROW(CalibrateTsai(line, Options()), std::invalid_argument);
  try {
    CalibrateTsaiViews({points, line}, Options());
    ADD_FAILURE() << "a collinear second view was taken";
  } catch (const std::invalid_argument& error) {
    EXPECT_EQ(std::string(error.what()).rfind("view 2: ", 0), 0u) << error.what();
  }
  std::vector<ControlPoint> shuffled = points;
  std::shuffle(shuffled.begin(), shuffled.end(), rng);
  for (size_t i = 0; i < points.size(); ++i) shuffled[i].point_in_world = points[i].point_in_world;
  EXPECT_THROW(CalibrateTsai(shuffled, Options()), std::invalid_argument);  // pixels paired with other points
  points[3].pixel.x() = std::nan("");
  EXPECT_THROW(CalibrateTsai(points, Options()), std::invalid_argument);
  TsaiCalibrationOptions options = Options();
  options.width = 0;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options = Options();
  options.pixel_mm = 0.0;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options = Options();
  options.max_kappa1_corner_sigma_px = 0.0;
  EXPECT_THROW(options.Check(), std::invalid_argument);
}

}  // namespace
}  // namespace mocap
