// Frames of another image size than the calibration's: a binned mode is rescaled onto the
// calibration's pixels, another aspect ratio is refused, both counted.
#include "ingest/image_size_check.h"

#include <gtest/gtest.h>

namespace mocap {
namespace {

CameraFrame Frame(uint32_t camera, uint32_t width, uint32_t height, std::vector<Eigen::Vector2d> pixels) {
  CameraFrame f;
  f.camera_id = camera;
  f.width = width;
  f.height = height;
  for (const Eigen::Vector2d& p : pixels) {
    Blob b;
    b.pixel = p;
    b.area = 9;
    f.blobs.push_back(b);
  }
  return f;
}

const ImageSizes kCalibrated = {{1, {1280, 800}}, {2, {1280, 800}}};

TEST(ImageSizeCheck, SizesOfTheCalibrationPassUnchanged) {
  ImageSizeCheck check(kCalibrated);
  CameraFrame f = Frame(1, 1280, 800, {{100.25, 50.5}});
  EXPECT_EQ(check.Apply(&f), ImageSizeVerdict::kSame);
  EXPECT_EQ(f.blobs[0].pixel, Eigen::Vector2d(100.25, 50.5));
  // No size reported, or a camera the calibration does not know: nothing to compare.
  CameraFrame unsized = Frame(1, 0, 0, {{100.25, 50.5}});
  EXPECT_EQ(check.Apply(&unsized), ImageSizeVerdict::kSame);
  CameraFrame other = Frame(7, 640, 480, {{1, 2}});
  EXPECT_EQ(check.Apply(&other), ImageSizeVerdict::kSame);
  EXPECT_TRUE(check.counts().empty());
  EXPECT_TRUE(check.Summary().empty());
}

TEST(ImageSizeCheck, ABinnedModeIsRescaledOntoTheCalibrationsPixels) {
  ImageSizeCheck check(kCalibrated);
  // 2x2 binning: binned pixel (i, j) covers full pixels 2i..2i+1, so its centre is 2i + 0.5; the
  // image centre stays the image centre, the first pixel's centre moves to 0.5.
  CameraFrame f = Frame(2, 640, 400, {{0.0, 0.0}, {319.5, 199.5}, {100.0, 300.25}});
  EXPECT_EQ(check.Apply(&f), ImageSizeVerdict::kRescaled);
  EXPECT_EQ(f.width, 1280u);
  EXPECT_EQ(f.height, 800u);
  EXPECT_NEAR((f.blobs[0].pixel - Eigen::Vector2d(0.5, 0.5)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((f.blobs[1].pixel - Eigen::Vector2d(639.5, 399.5)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((f.blobs[2].pixel - Eigen::Vector2d(200.5, 601.0)).norm(), 0.0, 1e-12);
  EXPECT_EQ(f.blobs[0].area, 36u);
  CameraFrame again = Frame(2, 640, 400, {{1, 1}});
  check.Apply(&again);
  ASSERT_EQ(check.counts().count(2), 1u);
  EXPECT_EQ(check.counts().at(2).rescaled_frames, 2u);
  EXPECT_EQ(check.counts().at(2).refused_frames, 0u);
  ASSERT_EQ(check.Summary().size(), 1u);
  EXPECT_EQ(check.Summary()[0], "camera 2: images of 640x400 against a calibration at 1280x800: 2 frames rescaled");
}

TEST(ImageSizeCheck, AnotherAspectRatioIsRefusedAndCounted) {
  ImageSizeCheck check(kCalibrated);
  CameraFrame f = Frame(1, 640, 480, {{10.0, 20.0}});
  EXPECT_EQ(check.Apply(&f), ImageSizeVerdict::kRefused);
  EXPECT_EQ(f.blobs[0].pixel, Eigen::Vector2d(10.0, 20.0));
  CameraFrame g = Frame(1, 1280, 720, {});
  EXPECT_EQ(check.Apply(&g), ImageSizeVerdict::kRefused);
  EXPECT_EQ(check.counts().at(1).refused_frames, 2u);
  EXPECT_EQ(check.counts().at(1).last_other.height, 720u);
  ASSERT_EQ(check.Summary().size(), 1u);
  EXPECT_NE(check.Summary()[0].find("2 frames refused (another aspect ratio)"), std::string::npos);
}

TEST(ImageSizeCheck, SizesComeFromTheRig) {
  Rig rig;
  rig.cameras.resize(2);
  rig.cameras[0].id = 4;
  rig.cameras[0].intrinsics.width = 1280;
  rig.cameras[0].intrinsics.height = 800;
  rig.cameras[1].id = 5;  // calibrated without a size: not checked
  const ImageSizes sizes = ImageSizesOf(rig);
  ASSERT_EQ(sizes.size(), 1u);
  EXPECT_EQ(sizes.at(4).width, 1280u);
  EXPECT_EQ(sizes.at(4).height, 800u);
}

}  // namespace
}  // namespace mocap
