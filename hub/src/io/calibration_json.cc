// Reads and writes the DESIGN.md calibration JSON; validates every field a Rig depends on.
#include "io/calibration_json.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "util/json_file.h"

namespace mocap {
namespace {

using nlohmann::json;

// A centroid noisier than this measures no marker (a blob is a few pixels wide).
constexpr double kMaxCentroidRmsPx = 50.0;

[[noreturn]] void Fail(const std::string& source, const std::string& reason) {
  throw std::runtime_error(source + ": " + reason);
}

// What a camera of this system can be, so that a damaged or hostile file (fx 1e308, distortion
// 1e10, 5000 cameras) is refused by name instead of poisoning every later computation. Each is
// far past any real lens or hall: a 3-degree telephoto on 1280 px has fx near 24000 (20 x width).
constexpr size_t kMaxCameras = 1024;
constexpr int kMaxImageSide = 1 << 16;
constexpr double kMaxFocalPerSide = 1000.0;   // fx, fy <= this x max(width, height)
constexpr double kMaxDistortion = 1000.0;     // |k1|, |k2|, |p1|, |p2|, |k3|
constexpr double kMaxTranslationMm = 1e7;     // 10 km from the world origin

void CheckRange(double value, double low, double high, const std::string& where, const std::string& source) {
  if (!(value >= low && value <= high)) {
    std::ostringstream rule;
    rule << where << ": " << value << " is out of range [" << low << ", " << high << "]";
    Fail(source, rule.str());
  }
}

double Number(const json& value, const std::string& where, const std::string& source) {
  if (!value.is_number()) Fail(source, where + " must be a number");
  const double number = value.get<double>();
  if (!std::isfinite(number)) Fail(source, where + " must be finite");
  return number;
}

const json& Field(const json& object, const char* name, const std::string& where,
                  const std::string& source) {
  const auto it = object.find(name);
  if (it == object.end()) Fail(source, where + ": missing \"" + name + "\"");
  return *it;
}

int PositiveInt(const json& value, const std::string& where, const std::string& source) {
  if (!value.is_number_integer() || value.get<int64_t>() <= 0 || value.get<int64_t>() > kMaxImageSide) {
    Fail(source, where + " must be a positive integer up to " + std::to_string(kMaxImageSide));
  }
  return value.get<int>();
}

Camera CameraFromJson(const json& entry, size_t index, const std::string& source) {
  std::string where = "camera #" + std::to_string(index);
  if (!entry.is_object()) Fail(source, where + " must be an object");
  Camera camera;
  const json& id = Field(entry, "id", where, source);
  if (!id.is_number_integer() || id.get<int64_t>() < 0 || id.get<int64_t>() > UINT32_MAX) {
    Fail(source, where + ": id must be a non-negative 32-bit integer");
  }
  camera.id = id.get<uint32_t>();
  where = "camera " + std::to_string(camera.id);

  CameraIntrinsics& in = camera.intrinsics;
  in.width = PositiveInt(Field(entry, "width", where, source), where + ": width", source);
  in.height = PositiveInt(Field(entry, "height", where, source), where + ": height", source);
  in.fx = Number(Field(entry, "fx", where, source), where + ": fx", source);
  in.fy = Number(Field(entry, "fy", where, source), where + ": fy", source);
  in.cx = Number(Field(entry, "cx", where, source), where + ": cx", source);
  in.cy = Number(Field(entry, "cy", where, source), where + ": cy", source);
  if (in.fx <= 0.0 || in.fy <= 0.0) Fail(source, where + ": fx and fy must be > 0");
  const double side = std::max(in.width, in.height);
  CheckRange(in.fx, 0.0, kMaxFocalPerSide * side, where + ": fx", source);
  CheckRange(in.fy, 0.0, kMaxFocalPerSide * side, where + ": fy", source);
  // The principal point lies near the image; a whole image away is already no lens.
  CheckRange(in.cx, -static_cast<double>(in.width), 2.0 * in.width, where + ": cx", source);
  CheckRange(in.cy, -static_cast<double>(in.height), 2.0 * in.height, where + ": cy", source);

  // OpenCV writes 4, 5, 8, 12 or 14 coefficients; this model has k1 k2 p1 p2 k3, so longer
  // vectors are accepted only when the terms it cannot represent are zero.
  const auto distortion = entry.find("distortion");
  if (distortion != entry.end()) {
    if (!distortion->is_array() || distortion->size() < 4) {
      Fail(source, where + ": distortion must be an array [k1, k2, p1, p2, k3]");
    }
    for (size_t i = 0; i < distortion->size(); ++i) {
      const double value = Number((*distortion)[i], where + ": distortion[" + std::to_string(i) + "]", source);
      if (i < 5) {
        CheckRange(value, -kMaxDistortion, kMaxDistortion, where + ": distortion[" + std::to_string(i) + "]", source);
        in.distortion[i] = value;
      } else if (value != 0.0) {
        Fail(source, where + ": distortion terms beyond k3 (rational/thin-prism) are not supported");
      }
    }
  }

  const json& rotation = Field(entry, "rotation", where, source);
  if (!rotation.is_array() || rotation.size() != 3) Fail(source, where + ": rotation must be 3x3");
  for (int r = 0; r < 3; ++r) {
    if (!rotation[r].is_array() || rotation[r].size() != 3) {
      Fail(source, where + ": rotation must be 3x3");
    }
    for (int c = 0; c < 3; ++c) {
      camera.rotation(r, c) = Number(rotation[r][c], where + ": rotation element", source);
    }
  }
  const double orthogonality =
      (camera.rotation * camera.rotation.transpose() - Eigen::Matrix3d::Identity()).norm();
  if (orthogonality > 1e-3 || camera.rotation.determinant() < 0.0) {
    Fail(source, where + ": rotation is not a rotation matrix (orthonormal, det +1)");
  }
  // Files carry rounded numbers; snap to the nearest rotation so later maths stays exact.
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(camera.rotation, Eigen::ComputeFullU | Eigen::ComputeFullV);
  camera.rotation = svd.matrixU() * svd.matrixV().transpose();

  const json& translation = Field(entry, "translation", where, source);
  if (!translation.is_array() || translation.size() != 3) {
    Fail(source, where + ": translation must be [tx, ty, tz]");
  }
  for (int i = 0; i < 3; ++i) {
    camera.translation[i] = Number(translation[i], where + ": translation element", source);
    CheckRange(camera.translation[i], -kMaxTranslationMm, kMaxTranslationMm,
               where + ": translation[" + std::to_string(i) + "]", source);
  }
  const auto noise = entry.find("centroid_rms_px");
  if (noise != entry.end()) {
    camera.centroid_rms_px = Number(*noise, where + ": centroid_rms_px", source);
    if (!(camera.centroid_rms_px >= 0.0 && camera.centroid_rms_px <= kMaxCentroidRmsPx)) {
      char reason[160];
      std::snprintf(reason, sizeof(reason), ": centroid_rms_px %g is out of range 0..%g (px)", camera.centroid_rms_px,
                    kMaxCentroidRmsPx);
      Fail(source, where + reason);
    }
  }
  return camera;
}

}  // namespace

Rig RigFromJson(const json& document, const std::string& source) {
  if (!document.is_object()) Fail(source, "top level must be a JSON object");
  const auto units = document.find("units");
  if (units != document.end() && !(units->is_string() && units->get<std::string>() == "mm")) {
    Fail(source, "units must be \"mm\"");
  }
  const auto cameras = document.find("cameras");
  if (cameras == document.end() || !cameras->is_array() || cameras->empty()) {
    Fail(source, "\"cameras\" must be a non-empty array");
  }
  if (cameras->size() > kMaxCameras) {
    Fail(source, "cameras: " + std::to_string(cameras->size()) + " is more than the " +
                     std::to_string(kMaxCameras) + " a rig may have");
  }
  Rig rig;
  std::set<uint32_t> ids;
  for (size_t i = 0; i < cameras->size(); ++i) {
    rig.cameras.push_back(CameraFromJson((*cameras)[i], i, source));
    if (!ids.insert(rig.cameras.back().id).second) {
      Fail(source, "camera id " + std::to_string(rig.cameras.back().id) + " appears twice");
    }
  }
  return rig;
}

json RigToJson(const Rig& rig) {
  json cameras = json::array();
  for (const Camera& camera : rig.cameras) {
    const CameraIntrinsics& in = camera.intrinsics;
    json rotation = json::array();
    for (int r = 0; r < 3; ++r) {
      rotation.push_back({camera.rotation(r, 0), camera.rotation(r, 1), camera.rotation(r, 2)});
    }
    cameras.push_back({{"id", camera.id},
                       {"width", in.width},
                       {"height", in.height},
                       {"fx", in.fx},
                       {"fy", in.fy},
                       {"cx", in.cx},
                       {"cy", in.cy},
                       {"distortion", in.distortion},
                       {"rotation", rotation},
                       {"translation",
                        {camera.translation.x(), camera.translation.y(), camera.translation.z()}}});
    if (camera.centroid_rms_px > 0.0) cameras.back()["centroid_rms_px"] = camera.centroid_rms_px;
  }
  return json{{"units", "mm"}, {"cameras", cameras}};
}

Rig LoadRigJson(const std::string& path) { return RigFromJson(ReadJsonFile(path), path); }

void SaveRigJson(const Rig& rig, const std::string& path) { WriteJsonFile(RigToJson(rig), path); }

json WithCameraPose(json document, const Camera& camera) {
  if (document.is_object() && document.contains("cameras") && document["cameras"].is_array()) {
    for (json& entry : document["cameras"]) {
      if (!entry.is_object() || !entry.contains("id") || !entry["id"].is_number_unsigned() ||
          entry["id"].get<uint64_t>() != camera.id)
        continue;
      json rotation = json::array();
      for (int r = 0; r < 3; ++r) rotation.push_back({camera.rotation(r, 0), camera.rotation(r, 1), camera.rotation(r, 2)});
      entry["rotation"] = rotation;
      entry["translation"] = {camera.translation.x(), camera.translation.y(), camera.translation.z()};
      return document;
    }
  }
  throw std::runtime_error("calibration document has no camera " + std::to_string(camera.id));
}

}  // namespace mocap
