// A one-line progress bar on stderr for long offline work (sim project, reconstruct, eval of
// long sessions). It draws only when stderr is a terminal, so logs and pipes stay clean. With a
// progress file it also keeps {"step", "done", "total"} there (replaced whole, at most ten times a
// second and at the end), for a program that runs the command and shows its progress (serve's
// processing jobs).
#pragma once

#include <chrono>
#include <cstddef>
#include <string>

namespace mocap {

class ProgressBar {
 public:
  ProgressBar(std::string label, size_t total, std::string progress_file = "");
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  // Redraws at most ten times a second (and at the end), so calling it per frame is cheap.
  void Update(size_t done);
  // Ends the line; called by the destructor too.
  void Finish();

  bool enabled() const { return enabled_; }

 private:
  void Draw(size_t done);
  void WriteFile(size_t done) const;

  std::string label_;
  size_t total_;
  bool enabled_;
  std::string progress_file_;
  bool finished_ = false;
  size_t last_done_ = 0;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
};

}  // namespace mocap
