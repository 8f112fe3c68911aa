// libFuzzer entry for the .mca archive reader: any bytes must decode or throw runtime_error naming
// the source; what decodes must expand to trajectories of the declared shape, and its encoding
// must decode to an archive that encodes to the same bytes (the range coder gives no single
// encoding of a chunk's values, so the check is that encoding is stable, not that it is the
// input).
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "archive/archive_format.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  mocap::CompressedTrajectories archive;
  try {
    archive = mocap::DecodeArchive(bytes, "fuzz");
  } catch (const std::runtime_error& error) {
    if (std::string(error.what()).rfind("fuzz: ", 0) != 0) __builtin_trap();
    return 0;
  }
  const mocap::MarkerTrajectories decoded = mocap::DecompressTrajectories(archive);
  if (decoded.points.size() != decoded.NumFrames() * decoded.NumMarkers()) __builtin_trap();
  std::string encoded;
  try {
    encoded = mocap::EncodeArchive(archive);
  } catch (const std::invalid_argument&) {
    // Values the writer refuses (a window under a byte per 1024 points once coded afresh).
    return 0;
  }
  if (mocap::EncodeArchive(mocap::DecodeArchive(encoded, "fuzz")) != encoded) __builtin_trap();
  return 0;
}
