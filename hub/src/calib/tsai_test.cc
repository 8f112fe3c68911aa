// Tsai blocks and .mcd recordings: parsing (the seed's own example block), the conversion to the
// OpenCV model against the exact Tsai projection, reconstruction through converted cameras, and
// one-line errors for malformed input.
#include "calib/tsai.h"

#include <cmath>
#include <fstream>
#include <utility>
#include <sstream>
#include <stdexcept>

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "calib/mcd.h"
#include "io/calibration_json.h"
#include "util/bounded_line.h"
#include "util/special_file_testing.h"
#include "geometry/triangulation.h"

namespace mocap {
namespace {

// The example block printed in seed 000 (section 4.2.2), one camera of a 320x240 webcam.
const char* kSeedBlock[19] = {"320.000000 //Ncx", "320.000000 //Nfx", "0.013000 //dx",    "0.013388 //dy",
                              "0.013000 //dpx",   "0.013388 //dpy",   "160.000000 //Cx",  "120.000000 //Cy",
                              "0.913305 //sx",    "5.556490 //f",     "-0.004061 //kappa1", "70.568381 //Tx",
                              "-33.763495 //Ty",  "481.087563 //Tz",  "-2.503010 //Rx",   "-0.416255 //Ry",
                              "-0.340617 //Rz",   "0.000000",         "0.0000001"};

std::vector<std::string> SeedBlock() { return std::vector<std::string>(kSeedBlock, kSeedBlock + 19); }

TEST(TsaiTest, ParsesTheSeedExampleBlock) {
  const TsaiCamera tsai = ParseTsaiBlock(SeedBlock(), "seed");
  EXPECT_DOUBLE_EQ(tsai.nfx, 320.0);
  EXPECT_DOUBLE_EQ(tsai.sx, 0.913305);
  EXPECT_DOUBLE_EQ(tsai.kappa1, -0.004061);
  EXPECT_DOUBLE_EQ(tsai.tz, 481.087563);
  EXPECT_DOUBLE_EQ(tsai.rz, -0.340617);
  EXPECT_DOUBLE_EQ(tsai.p2, 0.0000001);
  EXPECT_NEAR(tsai.Rotation().determinant(), 1.0, 1e-12);
}

TEST(TsaiTest, ConvertedCameraProjectsLikeTsai) {
  // (kappa1, largest acceptable fit error): the seed's lens, a mild pincushion, and a barrel
  // lens 15 % strong at the corners, where three OpenCV terms approximate Tsai's inverse less well.
  for (const auto& [kappa1, tolerance_px] : {std::pair{-0.004061, 0.01}, {0.01, 0.05}, {-0.02, 0.5}}) {
    TsaiCamera tsai = ParseTsaiBlock(SeedBlock(), "seed");
    tsai.kappa1 = kappa1;
    const TsaiConversion conversion = CameraFromTsai(tsai, 3, 320, 240);
    EXPECT_LT(conversion.max_error_px, tolerance_px) << kappa1;
    EXPECT_NEAR(conversion.camera.intrinsics.fx, 0.913305 * 5.556490 / 0.013, 1e-9);
    EXPECT_EQ(conversion.camera.intrinsics.height, 240);
    // World points across the view: the converted camera lands where Tsai's model does.
    const Camera& camera = conversion.camera;
    int compared = 0;
    for (double u = 10; u < 320; u += 50) {
      for (double v = 10; v < 240; v += 40) {
        const Eigen::Vector3d point = camera.CenterInWorld() + 450.0 * camera.RayDirectionInWorld({u, v});
        Eigen::Vector2d tsai_pixel, opencv_pixel;
        ASSERT_TRUE(tsai.Project(point, &tsai_pixel));
        ASSERT_TRUE(camera.ProjectToPixel(point, &opencv_pixel));
        EXPECT_LT((tsai_pixel - opencv_pixel).norm(), conversion.max_error_px + 1e-6);
        ++compared;
      }
    }
    EXPECT_GT(compared, 30);
  }
}

TEST(TsaiTest, MalformedBlocksAreRefused) {
  std::vector<std::string> block = SeedBlock();
  block.pop_back();
  EXPECT_THROW(ParseTsaiBlock(block, "x"), std::runtime_error);
  block = SeedBlock();
  block[9] = "five //f";
  EXPECT_THROW(ParseTsaiBlock(block, "x"), std::runtime_error);
  block = SeedBlock();
  block[4] = "0 //dpx";
  EXPECT_THROW(ParseTsaiBlock(block, "x"), std::runtime_error);
  block = SeedBlock();
  block[2] = "0.013 0.014";
  EXPECT_THROW(ParseTsaiBlock(block, "x"), std::runtime_error);
}

// What a block converts into must be a calibration the calibration reader loads: the Tsai-file
// fuzzer's Nfx 0.2 made a camera 0 px wide, 3e9 one of a negative width, f 1e308 an infinite
// focal length, and import-tsai wrote those into calibrations nothing could read.
TEST(TsaiTest, BlocksThatConvertIntoUnreadableCamerasAreRefused) {
  const auto refusal = [](size_t value, const std::string& text) {
    std::vector<std::string> block = SeedBlock();
    block[value] = text;
    try {
      ParseTsaiBlock(block, "x");
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(refusal(1, "0.2 //Nfx").find("Nfx must be an image width"), std::string::npos);
  EXPECT_NE(refusal(1, "3e9 //Nfx").find("Nfx must be an image width"), std::string::npos);
  EXPECT_NE(refusal(9, "1e308 //f").find("focal length"), std::string::npos);
  EXPECT_NE(refusal(4, "1e-320 //dpx").find("focal length"), std::string::npos);
  EXPECT_EQ(refusal(1, "1 //Nfx"), "accepted");
  const TsaiCamera tsai = ParseTsaiBlock(SeedBlock(), "seed");
  Rig rig;
  rig.cameras.push_back(CameraFromTsai(tsai, 1, 0, 0).camera);
  EXPECT_EQ(RigFromJson(RigToJson(rig), "imported").cameras.size(), 1u);
  EXPECT_EQ(rig.cameras[0].intrinsics.width, 320);
}

std::string BlockText(const TsaiCamera& t) {
  std::ostringstream out;
  out.precision(12);
  for (double v : {t.ncx, t.nfx, t.dx, t.dy, t.dpx, t.dpy, t.cx, t.cy, t.sx, t.f, t.kappa1, t.tx, t.ty, t.tz, t.rx,
                   t.ry, t.rz, t.p1, t.p2}) {
    out << v << "\n";
  }
  return out.str();
}

TEST(McdTest, RecordingReconstructsThroughConvertedCameras) {
  TsaiCamera left = ParseTsaiBlock(SeedBlock(), "seed");
  TsaiCamera right = left;
  // A second webcam 200 mm to the side, turned towards the same scene.
  right.ry += 0.35;
  right.tx -= 160.0;
  right.tz += 40.0;
  const Eigen::Vector3d marker(30.0, -20.0, 15.0);
  std::ostringstream text;
  text << "CameraCount: 2\n" << BlockText(left) << "\n" << BlockText(right) << "\n";
  Eigen::Vector2d a, b;
  ASSERT_TRUE(left.Project(marker, &a));
  ASSERT_TRUE(right.Project(marker, &b));
  text.precision(12);
  text << "Frame: 1\nmarksCount: 1 x = " << a.x() << " y = " << a.y() << "\nmarksCount: 1 x = " << b.x()
       << " y = " << b.y() << "\nFrame: 2\nmarksCount: 0\nmarksCount: 2 x = 1 y = 2 x = 3 y = 4\n";
  const McdRecording recording = ParseMcd(text.str(), "test.mcd");
  ASSERT_EQ(recording.cameras.size(), 2u);
  ASSERT_EQ(recording.frames.size(), 2u);
  EXPECT_EQ(recording.frames[1].frame_number, 2u);
  ASSERT_EQ(recording.frames[1].cameras.size(), 2u);
  EXPECT_TRUE(recording.frames[1].cameras[0].blobs.empty());
  EXPECT_EQ(recording.frames[1].cameras[1].blobs[1].pixel, Eigen::Vector2d(3, 4));
  EXPECT_EQ(recording.frames[1].cameras[1].camera_id, 2u);

  std::vector<PointView> views;
  for (size_t c = 0; c < 2; ++c) {
    const Camera camera = CameraFromTsai(recording.cameras[c], static_cast<uint32_t>(c + 1), 320, 240).camera;
    views.push_back({camera.ProjectionMatrix(), camera.UndistortPixel(recording.frames[0].cameras[c].blobs[0].pixel)});
  }
  Eigen::Vector3d reconstructed;
  ASSERT_TRUE(TriangulatePoint(views, &reconstructed));
  EXPECT_LT((reconstructed - marker).norm(), 0.5);
}

TEST(McdTest, MalformedRecordingsNameTheLine) {
  const std::string block = [] {
    std::string s;
    for (const char* line : kSeedBlock) s += std::string(line) + "\n";
    return s;
  }();
  auto expect_error = [](const std::string& text, const std::string& fragment) {
    try {
      ParseMcd(text, "bad.mcd");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const std::runtime_error& error) {
      EXPECT_NE(std::string(error.what()).find(fragment), std::string::npos) << error.what();
    }
  };
  expect_error("", "empty");
  expect_error("Cameras: 1\n", "CameraCount");
  expect_error("CameraCount: 2\n" + block, "19 values");
  expect_error("CameraCount: 1\n" + block + "\nFrame: 1\n", "ends before its camera 1");
  expect_error("CameraCount: 1\n" + block + "\nFrame: 1\nmarksCount: 2 x = 1 y = 2\n", "mark 2");
  expect_error("CameraCount: 1\n" + block + "\nFrame: 1\nmarksCount: 1 x = 1 y = 2 x = 3 y = 4\n", "more marks");
  expect_error("CameraCount: 1\n" + block + "\nFrame: 2\nmarksCount: 0\nFrame: 1\nmarksCount: 0\n", "increase");
  expect_error("CameraCount: 1\n" + block + "\nFrame: x\n", "Frame: K");
}

// A recording is read whole: a FIFO was waited on (and /dev/zero grew without end: not tried
// here, as without the check it would take all memory). Refused at once now, naming the path.
TEST(McdTest, ReadsOnlyRegularFiles) {
  const auto read = [](const std::string& path) { ReadMcd(path); };
  const std::string fifo = testing::ErrorOfReadingAFifo(read, "wand.mcd");
  EXPECT_NE(fifo.find("wand.mcd: not a regular file (a FIFO)"), std::string::npos) << fifo;
}

// A file whose line never ends (/dev/zero, a damaged file) is refused at 1 MiB, not read on.
TEST(TsaiTest, ALineWithoutEndIsRefused) {
  const std::string path = ::testing::TempDir() + "/endless_tsai.txt";
  std::ofstream(path) << std::string(kMaxTextLineBytes + 1, '\0');
  try {
    ReadTsaiFile(path);
    ADD_FAILURE() << "read";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(":1: longer than 1 MiB"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace mocap
