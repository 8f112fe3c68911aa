// Tests of the calibration JSON reader/writer: round trip, extra fields, and clear errors.
#include "io/calibration_json.h"

#include <fstream>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

namespace mocap {
namespace {

std::string WriteFile(const std::string& name, const std::string& text) {
  const std::string path = testing::TempDir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

// Expects loading `text` to fail with a message containing the file name and `reason`.
void ExpectLoadError(const std::string& text, const std::string& reason) {
  const std::string path = WriteFile("bad_rig.json", text);
  try {
    LoadRigJson(path);
    ADD_FAILURE() << "no error for: " << text;
  } catch (const std::runtime_error& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find(path), std::string::npos) << message;
    EXPECT_NE(message.find(reason), std::string::npos) << message;
  }
}

const char* kCamera =
    R"({"id": 3, "width": 1280, "height": 800, "fx": 1100.5, "fy": 1101.25, "cx": 640.0,
        "cy": 400.0, "distortion": [-0.2, 0.05, 0.001, 0.0, 0.0],
        "rotation": [[1,0,0],[0,1,0],[0,0,1]], "translation": [10, 20, 3000])";

TEST(CalibrationJsonTest, RoundTripIsExact) {
  Rig rig;
  for (uint32_t id : {1u, 4u}) {
    Camera camera;
    camera.id = id;
    camera.intrinsics = {1280, 800, 1100.123456789, 1099.5, 641.25, 399.75, {-0.21, 0.07, 1e-3, -2e-4, -0.013}};
    camera.rotation = Eigen::AngleAxisd(0.1 * id, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    camera.translation = Eigen::Vector3d(12.5, -300.25, 4000.0 + id);
    camera.centroid_rms_px = id == 1 ? 0.0 : 1.8765;  // unknown on one camera: not written
    rig.cameras.push_back(camera);
  }
  const std::string path = testing::TempDir() + "/rig_round_trip.json";
  SaveRigJson(rig, path);
  const Rig loaded = LoadRigJson(path);
  ASSERT_EQ(loaded.cameras.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    const Camera& a = rig.cameras[i];
    const Camera& b = loaded.cameras[i];
    EXPECT_EQ(a.id, b.id);
    EXPECT_EQ(a.intrinsics.width, b.intrinsics.width);
    EXPECT_EQ(a.intrinsics.height, b.intrinsics.height);
    EXPECT_EQ(a.intrinsics.fx, b.intrinsics.fx);
    EXPECT_EQ(a.intrinsics.fy, b.intrinsics.fy);
    EXPECT_EQ(a.intrinsics.cx, b.intrinsics.cx);
    EXPECT_EQ(a.intrinsics.cy, b.intrinsics.cy);
    EXPECT_EQ(a.intrinsics.distortion, b.intrinsics.distortion);
    EXPECT_LT((a.rotation - b.rotation).norm(), 1e-14);
    EXPECT_EQ(a.translation, b.translation);
    EXPECT_EQ(a.centroid_rms_px, b.centroid_rms_px);
  }
}

TEST(CalibrationJsonTest, IgnoresExtraFieldsAndAcceptsFourCoefficients) {
  const std::string path = WriteFile(
      "extra.json",
      R"({"units": "mm", "software": "x", "cameras": [{"id": 2, "serial": "abc", "fps": 120,
          "width": 640, "height": 480, "fx": 500, "fy": 500, "cx": 320, "cy": 240,
          "distortion": [0.1, 0.01, 0.0, 0.0], "rotation": [[1,0,0],[0,1,0],[0,0,1]],
          "translation": [0, 0, 0], "residuals": {"rms": 0.1}}]})");
  const Rig rig = LoadRigJson(path);
  ASSERT_EQ(rig.cameras.size(), 1u);
  EXPECT_EQ(rig.cameras[0].id, 2u);
  EXPECT_EQ(rig.cameras[0].intrinsics.distortion[0], 0.1);
  EXPECT_EQ(rig.cameras[0].intrinsics.distortion[4], 0.0);
}

TEST(CalibrationJsonTest, ClearErrors) {
  ExpectLoadError("{", "not valid JSON");
  ExpectLoadError("[]", "top level must be a JSON object");
  ExpectLoadError(R"({"cameras": []})", "non-empty array");
  ExpectLoadError(R"({"units": "m", "cameras": [)" + std::string(kCamera) + "}]}", "units");
  ExpectLoadError(R"({"cameras": [{"id": 1}]})", "missing \"width\"");
  ExpectLoadError(R"({"cameras": [)" + std::string(kCamera) + "}," + kCamera + "}]}", "appears twice");
  std::string camera = kCamera;
  ExpectLoadError(R"({"cameras": [)" + camera.replace(camera.find("1100.5"), 6, "-1.0") + "}]}",
                  "fx and fy must be > 0");
  camera = kCamera;
  ExpectLoadError(R"({"cameras": [)" + camera.replace(camera.find("[[1,0,0]"), 8, "[[2,0,0]") + "}]}",
                  "not a rotation matrix");
  camera = kCamera;
  ExpectLoadError(R"({"cameras": [)" + camera.replace(camera.find("[10, 20, 3000]"), 14, "[1, 2]") + "}]}",
                  "translation");
  camera = kCamera;
  ExpectLoadError(R"({"cameras": [)" + camera.replace(camera.find("0.0, 0.0]"), 9, "0.0, 0.0, 0.5]") + "}]}",
                  "beyond k3");
  camera = kCamera;
  ExpectLoadError(R"({"cameras": [)" + camera + R"(, "centroid_rms_px": -0.5}]})",
                  "camera 3: centroid_rms_px -0.5 is out of range 0..50 (px)");
  camera = kCamera;
  ExpectLoadError(R"({"cameras": [)" + camera + R"(, "centroid_rms_px": "2"}]})", "centroid_rms_px must be a number");
}

// The probe: reconstruct accepted fx 1e308, distortion 1e10 and 5000 cameras without a word.
TEST(CalibrationJsonTest, AbsurdValuesAreRefusedNamingTheField) {
  const auto with = [](const std::string& from, const std::string& to) {
    std::string camera = kCamera;
    camera.replace(camera.find(from), from.size(), to);
    return R"({"cameras": [)" + camera + "}]}";
  };
  ExpectLoadError(with("1100.5", "1e308"), "camera 3: fx: 1e+308 is out of range");
  ExpectLoadError(with("1101.25", "2e7"), "camera 3: fy: 2e+07 is out of range");
  ExpectLoadError(with("-0.2, 0.05", "-0.2, 1e10"), "camera 3: distortion[1]: 1e+10 is out of range");
  ExpectLoadError(with("\"cx\": 640.0", "\"cx\": 1e6"), "camera 3: cx: 1e+06 is out of range");
  ExpectLoadError(with("[10, 20, 3000]", "[10, 1e300, 3000]"), "camera 3: translation[1]");
  ExpectLoadError(with("\"width\": 1280", "\"width\": 1000000"), "width must be a positive integer up to 65536");
  std::string many = R"({"cameras": [)";
  for (int i = 0; i < 5000; ++i) {
    std::string camera = kCamera;
    camera.replace(camera.find("\"id\": 3"), 7, "\"id\": " + std::to_string(i));
    many += (i > 0 ? "}," : "") + camera;
  }
  ExpectLoadError(many + "}]}", "cameras: 5000 is more than the 1024");
}

TEST(CalibrationJsonTest, MissingFileNamesThePath) {
  try {
    LoadRigJson("/nonexistent/rig.json");
    ADD_FAILURE();
  } catch (const std::runtime_error& error) {
    EXPECT_EQ(std::string(error.what()), "/nonexistent/rig.json: cannot open: No such file or directory");
  }
}

}  // namespace
}  // namespace mocap
