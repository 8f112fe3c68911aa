// visibility.tsv: how many cameras saw each truth marker at each frame, written by the simulator
// beside truth.trc so eval can count as missing only markers that were reconstructible (seen by
// two or more cameras). Tab-separated: a "frame" + marker names header, then one row per frame.
// Errors follow the io layer policy (std::runtime_error "<file>: line N: <reason>").
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace mocap {

struct MarkerVisibility {
  std::vector<std::string> names;
  std::vector<uint64_t> frame_numbers;
  std::vector<uint16_t> counts;  // frame-major: counts[frame_index * names.size() + marker]

  size_t NumFrames() const { return frame_numbers.size(); }
  int At(size_t frame_index, size_t marker) const { return counts[frame_index * names.size() + marker]; }
};

MarkerVisibility ReadVisibility(const std::string& path);

// Streaming writer (flushed per frame, like the session log it accompanies).
class VisibilityWriter {
 public:
  VisibilityWriter() = default;
  ~VisibilityWriter();
  VisibilityWriter(const VisibilityWriter&) = delete;
  VisibilityWriter& operator=(const VisibilityWriter&) = delete;

  void Open(const std::string& path, const std::vector<std::string>& names);
  void WriteFrame(uint64_t frame_number, const std::vector<int>& cameras_seeing);
  void Close();

 private:
  std::FILE* file_ = nullptr;
  std::string path_;
  size_t num_markers_ = 0;
};

}  // namespace mocap
