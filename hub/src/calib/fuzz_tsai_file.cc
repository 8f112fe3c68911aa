// libFuzzer entry for Tsai camera files (`calibrate import-tsai`): any bytes as the file must read
// or throw runtime_error; cameras read must convert to the OpenCV model as the import does (or be
// refused with invalid_argument), into a calibration that the calibration reader accepts (what
// the import writes must load).
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "calib/tsai.h"
#include "io/calibration_json.h"
#include "util/fuzz_scratch_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const mocap::FuzzScratchFile scratch("tsai.txt");
  const std::string& path = scratch.Write(data, size);
  std::vector<mocap::TsaiCamera> cameras;
  try {
    cameras = mocap::ReadTsaiFile(path);
  } catch (const std::runtime_error& e) {
    if (std::string(e.what()).compare(0, path.size(), path) != 0) __builtin_trap();
    return 0;
  }
  if (cameras.empty()) __builtin_trap();
  mocap::Rig rig;
  try {
    for (size_t i = 0; i < cameras.size() && i < 4; ++i)
      rig.cameras.push_back(mocap::CameraFromTsai(cameras[i], static_cast<uint32_t>(i + 1), 0, 0).camera);
  } catch (const std::invalid_argument&) {
    return 0;  // a lens OpenCV's terms cannot fit: refused, as documented
  }
  try {
    mocap::RigFromJson(mocap::RigToJson(rig), "imported");
  } catch (const std::runtime_error&) {
    __builtin_trap();  // the import wrote a calibration nothing can read
  }
  return 0;
}
