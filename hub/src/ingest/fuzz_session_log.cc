// libFuzzer target: a session log file of arbitrary bytes read through the session reader.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "ingest/session.h"

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
  mocap::FrameSet set;
  while (reader.Next(&set)) {
  }
  return 0;
}
