// libFuzzer entry for DLT control point files (`calibrate dlt --points`): any bytes as the file
// must read or throw runtime_error naming the file; points read are finite, and a handful of them
// go through the DLT solve, which refuses degenerate sets with invalid_argument.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "calib/dlt.h"
#include "util/fuzz_scratch_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const mocap::FuzzScratchFile scratch("control_points.txt");
  const std::string& path = scratch.Write(data, size);
  std::vector<mocap::ControlPoint> points;
  try {
    points = mocap::ReadControlPoints(path);
  } catch (const std::runtime_error& e) {
    if (std::string(e.what()).compare(0, path.size(), path) != 0) __builtin_trap();
    return 0;
  }
  for (const mocap::ControlPoint& p : points)
    if (!p.point_in_world.allFinite() || !p.pixel.allFinite()) __builtin_trap();
  if (points.size() > 32) return 0;  // the solve's cost grows with the points, not the reader's
  mocap::DltOptions options;
  options.width = 640;
  options.height = 480;
  try {
    const mocap::DltResult result = mocap::CalibrateDlt(points, options);
    (void)result;
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
