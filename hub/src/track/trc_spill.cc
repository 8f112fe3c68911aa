// Binary spill of rows, converted to TRC at the end.
#include "track/trc_spill.h"

#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "io/marker_trajectories.h"
#include "io/trajectory_file.h"

namespace mocap {
namespace {

// One record per row: frame number, sample count, then (marker, x, y, z) per sample.
struct SpillSample {
  int32_t marker;
  float xyz[3];  // float keeps 0.1 um resolution at 10 m, far below what TRC prints
};

}  // namespace

TrcSpill::~TrcSpill() {
  if (spill_ != nullptr) {
    std::fclose(spill_);
    std::remove(spill_path_.c_str());
  }
}

void TrcSpill::Open(const std::string& trc_path, double rate_hz) {
  trc_path_ = trc_path;
  spill_path_ = trc_path + ".spill";
  rate_hz_ = rate_hz;
  spill_ = std::fopen(spill_path_.c_str(), "w+b");
  if (spill_ == nullptr) throw std::runtime_error(spill_path_ + ": cannot create spill file");
}

void TrcSpill::AddRow(uint64_t frame_number, const std::vector<TrackSample>& row) {
  const uint64_t count = row.size();
  bool ok = std::fwrite(&frame_number, sizeof frame_number, 1, spill_) == 1 &&
            std::fwrite(&count, sizeof count, 1, spill_) == 1;
  for (const TrackSample& sample : row) {
    SpillSample s{sample.marker,
                  {static_cast<float>(sample.position.x()), static_cast<float>(sample.position.y()),
                   static_cast<float>(sample.position.z())}};
    ok = ok && std::fwrite(&s, sizeof s, 1, spill_) == 1;
  }
  if (!ok) throw std::runtime_error(spill_path_ + ": write failed (disk full?)");
  ++rows_;
}

void TrcSpill::Finish(int num_markers) {
  std::vector<std::string> names;
  for (int m = 0; m < num_markers; ++m) names.push_back(DefaultMarkerName(m));
  if (names.empty()) throw std::runtime_error(trc_path_ + ": no marker was tracked; nothing to write");
  TrajectoryWriter writer;  // TRC or C3D, by the output's extension
  writer.Open(trc_path_, names, rate_hz_);
  std::rewind(spill_);
  std::vector<Eigen::Vector3d> points(num_markers);
  uint64_t frame_number = 0, count = 0;
  while (std::fread(&frame_number, sizeof frame_number, 1, spill_) == 1) {
    if (std::fread(&count, sizeof count, 1, spill_) != 1) {
      throw std::runtime_error(spill_path_ + ": truncated spill file");
    }
    std::fill(points.begin(), points.end(), MarkerTrajectories::Gap());
    for (uint64_t i = 0; i < count; ++i) {
      SpillSample s;
      if (std::fread(&s, sizeof s, 1, spill_) != 1) {
        throw std::runtime_error(spill_path_ + ": truncated spill file");
      }
      if (s.marker >= 0 && s.marker < num_markers) {
        points[s.marker] = Eigen::Vector3d(s.xyz[0], s.xyz[1], s.xyz[2]);
      }
    }
    writer.WriteFrame(frame_number, points);
  }
  writer.Close();
  std::fclose(spill_);
  spill_ = nullptr;
  std::remove(spill_path_.c_str());
}

}  // namespace mocap
