// Progress bar drawing: label, bar, percentage, count, rate and time left.
#include "cli/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

namespace mocap {

ProgressBar::ProgressBar(std::string label, size_t total, std::string progress_file)
    : label_(std::move(label)),
      total_(total),
      enabled_(isatty(STDERR_FILENO) == 1),
      progress_file_(std::move(progress_file)),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_ - std::chrono::seconds(1)) {}

ProgressBar::~ProgressBar() { Finish(); }

void ProgressBar::Update(size_t done) {
  last_done_ = done;
  if ((!enabled_ && progress_file_.empty()) || finished_) return;
  const auto now = std::chrono::steady_clock::now();
  if (done < total_ && now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  if (enabled_) Draw(done);
  WriteFile(done);
}

// Written beside and renamed over, so a reader never sees half a file; a failure to write is not
// the work's failure (the file only shows progress).
void ProgressBar::WriteFile(size_t done) const {
  if (progress_file_.empty()) return;
  const std::string partial = progress_file_ + ".partial";
  {
    std::ofstream out(partial, std::ios::trunc);
    out << nlohmann::json{{"step", label_}, {"done", done}, {"total", total_}}.dump() << "\n";
    if (!out) return;
  }
  std::error_code ec;
  std::filesystem::rename(partial, progress_file_, ec);
}

void ProgressBar::Draw(size_t done) {
  constexpr int kWidth = 30;
  const double fraction = total_ > 0 ? std::min(1.0, static_cast<double>(done) / total_) : 1.0;
  const int filled = static_cast<int>(fraction * kWidth);
  char bar[kWidth + 1];
  for (int i = 0; i < kWidth; ++i) bar[i] = i < filled ? '#' : '-';
  bar[kWidth] = '\0';
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double rate = seconds > 0.0 ? done / seconds : 0.0;
  const double left = rate > 0.0 ? (total_ - std::min(done, total_)) / rate : 0.0;
  std::fprintf(stderr, "\r%s [%s] %3.0f%% %zu/%zu  %.0f/s  %.0fs left ", label_.c_str(), bar, 100.0 * fraction,
               done, total_, rate, left);
  std::fflush(stderr);
}

void ProgressBar::Finish() {
  if (finished_) return;
  finished_ = true;
  WriteFile(last_done_);
  if (!enabled_) return;
  Draw(last_done_);
  std::fputc('\n', stderr);
}

}  // namespace mocap
