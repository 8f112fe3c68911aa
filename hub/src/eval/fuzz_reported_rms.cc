// libFuzzer entry for the reported reprojection figures eval-calibration reads from a calibration
// result (--result): any bytes as the file must read or throw runtime_error naming the file; what
// is read is finite-or-not as written but always under a camera id that fits 32 bits.
#include <cstddef>
#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>

#include "eval/calibration_eval.h"
#include "util/fuzz_scratch_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const mocap::FuzzScratchFile scratch("result.json");
  const std::string& path = scratch.Write(data, size);
  std::map<uint32_t, double> reported;
  try {
    reported = mocap::ReadReportedReprojectionRms(path);
  } catch (const std::runtime_error& e) {
    if (std::string(e.what()).compare(0, path.size(), path) != 0) __builtin_trap();
    return 0;
  }
  // Each entry came from one camera object of the file: never more entries than bytes allow.
  if (reported.size() * 30 > size + 30) __builtin_trap();
  return 0;
}
