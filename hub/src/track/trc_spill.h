// Streams tracked rows to a TRC or C3D file (by its extension) whose column count (the number of markers the tracker will
// have confirmed) is only known at the end: rows go to a compact binary spill file beside the
// output as they come, and Finish() converts it with the io layer's streaming writer. Memory
// stays constant; disk use is ~28 bytes per sample until Finish.
// Errors: std::runtime_error naming the file (io layer policy).
#pragma once

#include <cstdio>
#include <string>
#include <vector>

#include "track/tracker.h"

namespace mocap {

class TrcSpill {
 public:
  TrcSpill() = default;
  ~TrcSpill();
  TrcSpill(const TrcSpill&) = delete;
  TrcSpill& operator=(const TrcSpill&) = delete;

  void Open(const std::string& trc_path, double rate_hz);
  void AddRow(uint64_t frame_number, const std::vector<TrackSample>& row);
  // Writes the TRC with names M001... for num_markers columns and removes the spill file.
  void Finish(int num_markers);
  uint64_t rows() const { return rows_; }

 private:
  std::string trc_path_;
  std::string spill_path_;
  double rate_hz_ = 0.0;
  std::FILE* spill_ = nullptr;
  uint64_t rows_ = 0;
};

}  // namespace mocap
