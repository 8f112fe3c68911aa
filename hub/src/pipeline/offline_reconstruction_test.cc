// The offline chain on a simulated rig, rows collected in memory instead of a file: one row per
// frame in frame order, one column per marker that stays on it, a marker hidden from every
// camera for a few frames filled in, frame sets out of order skipped, the spline filling only
// when its option allows the gap.
#include "pipeline/offline_reconstruction.h"

#include <algorithm>
#include <map>
#include <vector>

#include <gtest/gtest.h>

#include "simcore/test_scenes.h"

namespace mocap::pipeline {
namespace {

constexpr double kRateHz = 120.0;
constexpr int kFrames = 240;
constexpr int kHidden = 3;                   // the marker hidden from every camera ...
constexpr int kHiddenFrom = 100, kHiddenTo = 103;  // ... in these frames [from, to)

struct Row {
  uint64_t frame = 0;
  std::vector<TrackSample> samples;
};

class OfflineReconstructionTest : public ::testing::Test {
 protected:
  OfflineReconstructionTest()
      : rig_(testing::MakeRingRig(8, 4000.0, 2200.0, Eigen::Vector3d(0, 0, 1000))),
        motion_(12, 4, 11),
        projector_(rig_, Faults(), 12) {}

  static testing::ProjectionFaults Faults() {
    testing::ProjectionFaults faults;
    faults.noise_px = 0.2;
    faults.occlusion = 0.02;
    faults.occlusion_frames = 3;
    return faults;
  }

  // Frame f with marker kHidden's blobs taken out of every camera in the hidden frames.
  FrameSet Frame(uint64_t f) {
    FrameSet set;
    testing::BlobTruth truth;
    projector_.Project(f, motion_.At(static_cast<double>(f) / kRateHz), &set, &truth);
    if (f < kHiddenFrom || f >= kHiddenTo) return set;
    for (size_t c = 0; c < set.cameras.size(); ++c) {
      std::vector<Blob> kept;
      for (size_t b = 0; b < set.cameras[c].blobs.size(); ++b)
        if (truth[c][b] != kHidden) kept.push_back(set.cameras[c].blobs[b]);
      set.cameras[c].blobs = kept;
    }
    return set;
  }

  Rig rig_;
  testing::SyntheticMotion motion_;
  testing::FrameProjector projector_;
};

TEST_F(OfflineReconstructionTest, OneRowPerFrameOneColumnPerMarkerGapsFilled) {
  std::vector<Row> rows;
  OfflineReconstruction chain(rig_, kRateHz, {}, [&rows](uint64_t frame, const std::vector<TrackSample>& row) {
    rows.push_back({frame, row});
  });
  for (int f = 0; f < kFrames; ++f) {
    const FrameSet set = Frame(f);
    ASSERT_TRUE(chain.Add(set));
    EXPECT_FALSE(chain.points().empty());
    EXPECT_FALSE(chain.Add(set)) << "a frame set not after the last one is skipped";
  }
  EXPECT_EQ(chain.frames(), static_cast<size_t>(kFrames));
  const int columns = chain.Finish();
  EXPECT_EQ(columns, motion_.NumMarkers());

  ASSERT_EQ(rows.size(), static_cast<size_t>(kFrames));
  std::map<int, int> truth_of_column;
  for (size_t r = 0; r < rows.size(); ++r) {
    ASSERT_EQ(rows[r].frame, r);
    const std::vector<Eigen::Vector3d> truth = motion_.At(static_cast<double>(r) / kRateHz);
    for (const TrackSample& s : rows[r].samples) {
      ASSERT_GE(s.marker, 0);
      ASSERT_LT(s.marker, columns);
      EXPECT_EQ(s.frame_number, rows[r].frame);
      int nearest = 0;
      for (int m = 1; m < static_cast<int>(truth.size()); ++m)
        if ((truth[m] - s.position).norm() < (truth[nearest] - s.position).norm()) nearest = m;
      EXPECT_LT((truth[nearest] - s.position).norm(), 5.0) << "frame " << r << " column " << s.marker;
      const auto [it, inserted] = truth_of_column.emplace(s.marker, nearest);
      EXPECT_EQ(it->second, nearest) << "frame " << r << ": column " << s.marker << " changed marker";
    }
  }
  ASSERT_EQ(truth_of_column.size(), static_cast<size_t>(columns));

  int hidden_column = -1;
  for (const auto& [column, truth] : truth_of_column)
    if (truth == kHidden) hidden_column = column;
  ASSERT_GE(hidden_column, 0);
  for (int f = kHiddenFrom; f < kHiddenTo; ++f) {
    const std::vector<TrackSample>& row = rows[f].samples;
    const auto it =
        std::find_if(row.begin(), row.end(), [&](const TrackSample& s) { return s.marker == hidden_column; });
    ASSERT_NE(it, row.end()) << "frame " << f << ": the hidden marker's gap is not filled";
    EXPECT_NE(it->kind, SampleKind::kMeasured) << "frame " << f;
  }
}

TEST_F(OfflineReconstructionTest, SplineGapFollowsItsOption) {
  // The samples the spline filled, in the rows and in the filler's count, with a spline gap of
  // `max_spline_gap_s` (the hidden frames are 3 of 120 Hz, 0.025 s).
  auto filled = [this](double max_spline_gap_s, long long* counted) {
    OfflineReconstructionOptions options;
    options.max_spline_gap_s = max_spline_gap_s;
    long long in_rows = 0;
    OfflineReconstruction chain(rig_, kRateHz, options, [&](uint64_t, const std::vector<TrackSample>& row) {
      for (const TrackSample& s : row) in_rows += s.kind == SampleKind::kFilled;
    });
    for (int f = 0; f < kFrames; ++f) chain.Add(Frame(f));
    chain.Finish();
    *counted = chain.gap_filler().filled_samples();
    return in_rows;
  };
  long long counted = 0;
  const long long with_spline = filled(0.05, &counted);
  EXPECT_GT(with_spline, 0);
  EXPECT_EQ(counted, with_spline);
  EXPECT_EQ(filled(0.0, &counted), 0);
  EXPECT_EQ(counted, 0);
}

}  // namespace
}  // namespace mocap::pipeline
