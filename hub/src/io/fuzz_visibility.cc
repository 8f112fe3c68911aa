// libFuzzer entry for visibility.tsv (eval's per-frame camera counts of the truth markers): any
// bytes as the file must read or throw runtime_error naming the file; a table read must be
// written by VisibilityWriter and read back unchanged.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/visibility.h"
#include "util/fuzz_scratch_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const mocap::FuzzScratchFile scratch("visibility.tsv");
  static const mocap::FuzzScratchFile written("visibility.tsv.again");
  const std::string& path = scratch.Write(data, size);
  mocap::MarkerVisibility visibility;
  try {
    visibility = mocap::ReadVisibility(path);
  } catch (const std::runtime_error& e) {
    if (std::string(e.what()).compare(0, path.size(), path) != 0) __builtin_trap();
    return 0;
  }
  if (visibility.counts.size() != visibility.NumFrames() * visibility.names.size()) __builtin_trap();
  mocap::VisibilityWriter writer;
  writer.Open(written.path(), visibility.names);
  for (size_t f = 0; f < visibility.NumFrames(); ++f) {
    std::vector<int> row;
    for (size_t m = 0; m < visibility.names.size(); ++m) row.push_back(visibility.At(f, m));
    writer.WriteFrame(visibility.frame_numbers[f], row);
  }
  writer.Close();
  const mocap::MarkerVisibility back = mocap::ReadVisibility(written.path());
  if (back.names != visibility.names || back.frame_numbers != visibility.frame_numbers ||
      back.counts != visibility.counts)
    __builtin_trap();
  return 0;
}
