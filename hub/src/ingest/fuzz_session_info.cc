// libFuzzer entry for the session description (session.json): any bytes as a session directory's
// session.json, beside a raw log of two frames, must open through SessionReader or throw
// runtime_error; a description that loads must be written and read back unchanged (extra fields
// too), and the session's frames read past it.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "ingest/session.h"

namespace {

namespace fs = std::filesystem;

bool Same(const mocap::SessionInfo& a, const mocap::SessionInfo& b) {
  return a.rate_hz == b.rate_hz && a.epoch_ns == b.epoch_ns && a.free_run == b.free_run &&
         a.camera_ids == b.camera_ids && a.frame_sets == b.frame_sets && a.camera_frames == b.camera_frames &&
         a.dropped_camera_frames == b.dropped_camera_frames && a.calibration == b.calibration && a.log == b.log &&
         a.source == b.source && a.extra == b.extra;
}

// A session directory of this process with a raw log of two frames (written once, by the
// project's own writer), removed when the process exits; each input replaces its session.json.
class ScratchSession {
 public:
  ScratchSession() : dir_(fs::temp_directory_path() / ("mocap_fuzz_" + std::to_string(::getpid()) + "_session")) {
    fs::remove_all(dir_);
    mocap::SessionInfo info;
    info.rate_hz = 100.0;
    info.camera_ids = {1, 2};
    mocap::SessionWriter writer;
    writer.Create(dir_.string(), info);
    for (uint32_t camera : {1u, 2u}) {
      for (uint64_t frame : {0u, 1u}) {
        mocap::CameraFrame f;
        f.camera_id = camera;
        f.frame_number = frame;
        f.width = 640;
        f.height = 480;
        f.blobs.push_back({Eigen::Vector2d(100.0 + frame, 200.0), 12, 200, 150, 0});
        writer.Write(f);
      }
    }
    writer.Finish();
  }
  ~ScratchSession() {
    std::error_code ignored;
    fs::remove_all(dir_, ignored);
  }
  const fs::path& dir() const { return dir_; }

 private:
  fs::path dir_;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const ScratchSession session;
  const fs::path& dir = session.dir();
  {
    std::ofstream out(dir / "session.json", std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  mocap::SessionReader reader;
  try {
    reader.Open(dir.string());
  } catch (const std::runtime_error&) {
    return 0;
  }
  const mocap::SessionInfo& info = reader.Info();
  const mocap::SessionInfo again = mocap::SessionInfo::FromJson(info.ToJson());
  if (!Same(info, again)) __builtin_trap();
  mocap::FrameSet set;
  size_t sets = 0;
  while (reader.Next(&set)) ++sets;
  if (sets > 2) __builtin_trap();
  return 0;
}
