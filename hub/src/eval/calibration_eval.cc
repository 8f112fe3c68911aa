// Rigid alignment by Kabsch on camera centres (geometry/rigid_fit.h), then per-camera differences.
// Centre errors are measured after the rigid (not the similarity) fit, so that a scale error
// shows up in them as well as in scale_error.
#include "eval/calibration_eval.h"

#include <cmath>
#include <fstream>
#include <limits>
#include <stdexcept>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "geometry/rigid_fit.h"
#include "util/json_file.h"

namespace mocap {

CalibrationEval EvaluateCalibration(const Rig& truth, const Rig& result,
                                    const std::map<uint32_t, double>& reported_rms_px,
                                    const CalibrationEvalOptions& options) {
  CalibrationEval eval;
  std::vector<const Camera*> expected, actual;
  for (const Camera& camera : truth.cameras) {
    const Camera* found = result.Find(camera.id);
    if (found == nullptr) {
      eval.missing.push_back(camera.id);
      continue;
    }
    expected.push_back(&camera);
    actual.push_back(found);
  }
  if (expected.empty()) throw std::invalid_argument("no camera id of the truth appears in the result");

  SimilarityTransform truth_from_result;  // identity unless aligned
  std::vector<Eigen::Vector3d> source, target;
  for (size_t i = 0; i < expected.size(); ++i) {
    source.push_back(actual[i]->CenterInWorld());
    target.push_back(expected[i]->CenterInWorld());
  }
  if (options.align) {
    if (expected.size() < 3) {
      throw std::invalid_argument("aligning the world frames needs at least 3 cameras in both rigs");
    }
    truth_from_result = FitRigid(source, target);
    eval.aligned = true;
  }
  if (expected.size() >= 3) eval.scale_error = 1.0 / FitSimilarity(source, target).scale - 1.0;

  double centre_sq = 0.0, rotation_sq = 0.0, rms_sum = 0.0;
  int rms_count = 0;
  for (size_t i = 0; i < expected.size(); ++i) {
    CameraCalibrationError error;
    error.id = expected[i]->id;
    error.centre_error_mm = (truth_from_result.Apply(source[i]) - target[i]).norm();
    // cam_from_truth = cam_from_result * result_from_truth.
    const Eigen::Matrix3d aligned = actual[i]->rotation * truth_from_result.rotation.transpose();
    error.rotation_error_deg = Eigen::AngleAxisd(aligned * expected[i]->rotation.transpose()).angle() * 180.0 / M_PI;
    const CameraIntrinsics& a = actual[i]->intrinsics;
    const CameraIntrinsics& e = expected[i]->intrinsics;
    error.focal_error_percent = 50.0 * ((a.fx - e.fx) / e.fx + (a.fy - e.fy) / e.fy);
    const auto reported = reported_rms_px.find(error.id);
    if (reported != reported_rms_px.end()) {
      error.reprojection_rms_px = reported->second;
      rms_sum += reported->second;
      ++rms_count;
    }
    centre_sq += error.centre_error_mm * error.centre_error_mm;
    rotation_sq += error.rotation_error_deg * error.rotation_error_deg;
    eval.centre_max_mm = std::max(eval.centre_max_mm, error.centre_error_mm);
    eval.rotation_max_deg = std::max(eval.rotation_max_deg, error.rotation_error_deg);
    eval.cameras.push_back(error);
  }
  const double n = static_cast<double>(eval.cameras.size());
  eval.centre_rms_mm = std::sqrt(centre_sq / n);
  eval.rotation_rms_deg = std::sqrt(rotation_sq / n);
  if (rms_count > 0) eval.reprojection_rms_px = rms_sum / rms_count;
  return eval;
}

std::map<uint32_t, double> ReadReportedReprojectionRms(const std::string& path) {
  const nlohmann::json document = ReadJsonFile(path);
  std::map<uint32_t, double> reported;
  const auto cameras = document.find("cameras");
  if (cameras == document.end() || !cameras->is_array()) return reported;
  for (const auto& camera : *cameras) {
    if (!camera.is_object()) continue;
    const auto id = camera.find("id");
    const auto rms = camera.find("reprojection_rms_px");
    if (id == camera.end() || rms == camera.end() || !id->is_number_unsigned() || !rms->is_number()) continue;
    // No camera has an id past 32 bits: such an entry is not one (it would wrap onto another's).
    if (id->get<uint64_t>() > std::numeric_limits<uint32_t>::max()) continue;
    reported[static_cast<uint32_t>(id->get<uint64_t>())] = rms->get<double>();
  }
  return reported;
}

}  // namespace mocap
