// libFuzzer target: a session log file of arbitrary bytes read through the session reader, with
// the frame numbers driving a gap filler as `reconstruct` does. Forged frame numbers (seeds
// frame_*) once made that step allocate a row per frame number; the row count is now checked
// against what the log holds, so such a regression aborts the run.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "ingest/session.h"
#include "track/gap_filler.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::filesystem::path dir = [] {
    auto d = std::filesystem::temp_directory_path() / ("mocap_fuzz_session_" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    std::ofstream(d / "session.json") << R"({"format":"mocap-session","version":1,"rate_hz":100,"cameras":[1]})";
    return d;
  }();
  {
    std::ofstream log(dir / "raw.mlog", std::ios::binary | std::ios::trunc);
    log.write("MOCAPLOG\x01\0\0\0\0\0\0\0", 16);
    log.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  mocap::SessionReader reader(4);
  reader.Open(dir.string());
  mocap::GapFillOptions options;
  options.window_frames = 16;
  uint64_t rows = 0, sets = 0;
  mocap::GapFiller filler(options, [&rows](uint64_t, const std::vector<mocap::TrackSample>&) { ++rows; });
  mocap::FrameSet set;
  while (reader.Next(&set)) {
    ++sets;
    filler.Add(set.frame_number, {});
    if (rows > sets * (options.window_frames + 1)) std::abort();
  }
  filler.Finish();
  if (rows > sets * (options.window_frames + 1)) std::abort();
  return 0;
}
