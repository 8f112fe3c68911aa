// Frame loading for the benchmark: finds the camera directories, then reads each frames.mcf
// with the framefile reader into owned buffers.
#include "detect-bench/frame_set.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "framefile/framefile.h"

namespace mocap {
namespace fs = std::filesystem;

namespace {

std::vector<fs::path> CameraDirs(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw std::runtime_error("frames directory not found: " + dir.string());
  if (fs::exists(dir / MN_FF_FILE_NAME, ec)) return {dir};
  std::vector<fs::path> cams;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_directory() && name.rfind("cam", 0) == 0 &&
        fs::exists(entry.path() / MN_FF_FILE_NAME))
      cams.push_back(entry.path());
  }
  if (ec) throw std::runtime_error("cannot list " + dir.string() + ": " + ec.message());
  if (cams.empty())
    throw std::runtime_error(dir.string() + " holds neither " MN_FF_FILE_NAME
                             " nor cam*/" MN_FF_FILE_NAME);
  std::sort(cams.begin(), cams.end());
  return cams;
}

}  // namespace

std::vector<BenchFrame> LoadFrames(const std::string& dir, size_t max_frames) {
  std::vector<BenchFrame> frames;
  for (const fs::path& cam : CameraDirs(dir)) {
    const char* why = nullptr;
    mn_ff_reader* rd = mn_ff_reader_open(cam.c_str(), &why);
    if (!rd) throw std::runtime_error(cam.string() + ": " + why);
    const mn_ff_info* info = mn_ff_reader_info(rd);
    while (frames.size() < max_frames) {
      BenchFrame f;
      f.width = info->width;
      f.height = info->height;
      f.camera = cam.filename().string();
      f.pixels.resize(static_cast<size_t>(f.width) * f.height);
      const int rc = mn_ff_reader_next(rd, f.pixels.data(), f.width, nullptr);
      if (rc < 0) {
        mn_ff_reader_close(rd);
        throw std::runtime_error(cam.string() + ": read error");
      }
      if (rc == 0) break;
      frames.push_back(std::move(f));
    }
    if (mn_ff_reader_damaged(rd))
      std::fprintf(stderr, "warning: %s: %s\n", cam.c_str(), mn_ff_reader_message(rd));
    mn_ff_reader_close(rd);
  }
  if (frames.empty()) throw std::runtime_error("no frames found in " + dir);
  return frames;
}

}  // namespace mocap
