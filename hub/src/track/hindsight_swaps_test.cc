// Hindsight swap repair: trades of one, two frames and for good are undone; markers that pass
// close by, noise and late samples are left as they are; rigid clusters keep their shape.
#include "track/hindsight_swaps.h"

#include <map>
#include <random>

#include <gtest/gtest.h>

namespace mocap {
namespace {

// Two markers 20 mm apart on a curved, accelerating path (a limb's cluster).
Eigen::Vector3d TrueAt(int marker, int frame) {
  const double f = frame;
  return Eigen::Vector3d(3.0 * f + 0.05 * f * f, 100.0 + 10.0 * std::sin(f / 15.0), 20.0 * marker);
}

using Output = std::map<uint64_t, std::map<int, Eigen::Vector3d>>;

// Feeds `frames` frames of the two markers; traded(frame) says whether the tracker gave each
// marker's column the other's point in that frame.
template <typename Traded>
Output RunTwoMarkers(const HindsightSwapOptions& options, int frames, Traded traded, long long* undone) {
  Output out;
  HindsightSwaps repair(options, [&](uint64_t frame, const std::vector<TrackSample>& row) {
    for (const TrackSample& s : row) {
      EXPECT_EQ(out[s.frame_number].count(s.marker), 0u) << "frame " << s.frame_number;
      out[s.frame_number][s.marker] = s.position;
    }
    (void)frame;
  });
  for (int f = 0; f < frames; ++f) {
    std::vector<TrackSample> samples;
    for (int marker = 0; marker < 2; ++marker) {
      TrackSample s;
      s.marker = marker;
      s.frame_number = static_cast<uint64_t>(f);
      s.position = TrueAt(traded(f) ? 1 - marker : marker, f);
      samples.push_back(s);
    }
    repair.Add(static_cast<uint64_t>(f), samples);
  }
  repair.Finish();
  *undone = repair.swaps_undone();
  return out;
}

void ExpectUntraded(const Output& out, int frames) {
  ASSERT_EQ(out.size(), static_cast<size_t>(frames));
  for (const auto& [frame, columns] : out) {
    for (const auto& [marker, position] : columns) {
      EXPECT_LT((position - TrueAt(marker, static_cast<int>(frame))).norm(), 1e-9)
          << "frame " << frame << " column " << marker;
    }
  }
}

TEST(HindsightSwaps, OneFrameTradeIsUndone) {
  long long undone = 0;
  const Output out = RunTwoMarkers(HindsightSwapOptions(), 40, [](int f) { return f == 17; }, &undone);
  ExpectUntraded(out, 40);
  EXPECT_EQ(undone, 1);
}

TEST(HindsightSwaps, TwoFrameTradeIsUndone) {
  long long undone = 0;
  const Output out = RunTwoMarkers(HindsightSwapOptions(), 40, [](int f) { return f == 17 || f == 18; }, &undone);
  ExpectUntraded(out, 40);
  EXPECT_EQ(undone, 1);
}

TEST(HindsightSwaps, TradeForGoodIsUndoneForLaterFramesToo) {
  long long undone = 0;
  const Output out = RunTwoMarkers(HindsightSwapOptions(), 60, [](int f) { return f >= 17; }, &undone);
  ExpectUntraded(out, 60);
  EXPECT_EQ(undone, 1);
}

TEST(HindsightSwaps, TradesAreKeptWhenDisabled) {
  HindsightSwapOptions options;
  options.enabled = false;
  long long undone = 0;
  const Output out = RunTwoMarkers(options, 40, [](int f) { return f == 17; }, &undone);
  EXPECT_EQ(undone, 0);
  EXPECT_LT((out.at(17).at(0) - TrueAt(1, 17)).norm(), 1e-9);
}

TEST(HindsightSwaps, MarkersPassingCloseAndNoiseAreLeftAlone) {
  // Two markers cross 4 mm apart at speed, with 0.5 mm noise: every row comes out as given.
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.5);
  Output given, out;
  HindsightSwaps repair(HindsightSwapOptions(), [&](uint64_t, const std::vector<TrackSample>& row) {
    for (const TrackSample& s : row) out[s.frame_number][s.marker] = s.position;
  });
  for (int f = 0; f < 80; ++f) {
    std::vector<TrackSample> samples;
    for (int marker = 0; marker < 2; ++marker) {
      TrackSample s;
      s.marker = marker;
      s.frame_number = static_cast<uint64_t>(f);
      const double direction = marker == 0 ? 1.0 : -1.0;
      s.position = Eigen::Vector3d(direction * 4.0 * (f - 40), 4.0 * marker, 0.02 * f * f) +
                   Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
      given[s.frame_number][s.marker] = s.position;
      samples.push_back(s);
    }
    repair.Add(static_cast<uint64_t>(f), samples);
  }
  repair.Finish();
  EXPECT_EQ(repair.swaps_undone(), 0);
  ASSERT_EQ(out.size(), given.size());
  for (const auto& [frame, columns] : given) {
    for (const auto& [marker, position] : columns) EXPECT_EQ(out[frame][marker], position);
  }
}

// Three markers of a fast cluster (30 mm apart, 40 mm per frame): `label(f, m)` is the column
// the tracker gave marker m's point in frame f.
template <typename Label>
Output RunCluster(int frames, Label label, const std::vector<std::pair<int, Eigen::Vector3d>>& glitches,
                  long long* undone) {
  const auto at = [](int marker, int f) {
    return Eigen::Vector3d(40.0 * f + 0.3 * f * f, 30.0 * marker, 5.0 * std::sin(f / 7.0) + 10.0 * (marker == 2));
  };
  Output out;
  HindsightSwaps repair(HindsightSwapOptions(), [&](uint64_t, const std::vector<TrackSample>& row) {
    for (const TrackSample& s : row) out[s.frame_number][s.marker] = s.position;
  });
  for (int f = 0; f < frames; ++f) {
    std::vector<TrackSample> samples;
    for (int marker = 0; marker < 3; ++marker) {
      TrackSample s;
      s.marker = label(f, marker);
      s.frame_number = static_cast<uint64_t>(f);
      s.position = at(marker, f);
      for (const auto& [frame, offset] : glitches) {
        if (frame == f && marker == 0) s.position += offset;
      }
      samples.push_back(s);
    }
    repair.Add(static_cast<uint64_t>(f), samples);
  }
  repair.Finish();
  *undone = repair.swaps_undone();
  for (auto& [frame, columns] : out) {
    for (auto& [marker, position] : columns) position -= at(marker, static_cast<int>(frame));
  }
  return out;  // what each column misses its own marker by
}

TEST(HindsightSwaps, JumbledStartIsLabelledBackFromLaterFrames) {
  // The first two frames' labels are passed round among the three markers (births without
  // velocities), then the tracks settle.
  long long undone = 0;
  const Output miss = RunCluster(
      40, [](int f, int m) { return f < 2 ? (m + 1 + f) % 3 : m; }, {}, &undone);
  ASSERT_EQ(miss.size(), 40u);
  for (const auto& [frame, columns] : miss) {
    for (const auto& [marker, offset] : columns) EXPECT_LT(offset.norm(), 1e-9) << frame << " " << marker;
  }
  EXPECT_EQ(undone, 2);
}

TEST(HindsightSwaps, AMarkerThatJumpsAloneKeepsItsSamples) {
  // Marker 0 is 15 mm off in frame 20 and 12 mm in frame 31 (bad triangulations, no trade).
  long long undone = 0;
  const Output miss = RunCluster(
      50, [](int, int m) { return m; },
      {{20, Eigen::Vector3d(0.0, 15.0, 0.0)}, {31, Eigen::Vector3d(8.0, 0.0, 9.0)}}, &undone);
  EXPECT_EQ(undone, 0);
  ASSERT_EQ(miss.size(), 50u);
  for (const auto& [frame, columns] : miss) {
    for (const auto& [marker, offset] : columns) {
      const bool glitch = marker == 0 && (frame == 20 || frame == 31);
      EXPECT_EQ(offset.norm() > 1.0, glitch) << frame << " " << marker;
    }
  }
}

// A rigid cluster: a base marker and two 18.6 and 27.8 mm from it, 90 degrees apart, on a
// curving path. From frame `flip` on the cluster is turned over in one frame (the two outer markers'
// directions exchange): each marker keeps its distances, and its nearest point in the next frame
// is the other outer marker's (a trade, to smoothness alone). `traded(f)` gives the tracker's
// columns 1 and 2 each other's points. Returns what each column misses its own marker by.
template <typename Traded>
Output RunFlippingCluster(const HindsightSwapOptions& options, int frames, int flip, Traded traded,
                          long long* undone) {
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, 0.2);
  const auto at = [&](int marker, int f) {
    const Eigen::Vector3d base(5.0 * f + 0.02 * f * f, 100.0 + 20.0 * std::sin(f / 20.0), 0.0);
    const double phi = 0.02 * f;
    const Eigen::Vector3d u1(std::cos(phi), std::sin(phi), 0.0), u2(-std::sin(phi), std::cos(phi), 0.0);
    const bool flipped = f >= flip;
    if (marker == 0) return base;
    if (marker == 1) return Eigen::Vector3d(base + 18.6 * (flipped ? u2 : u1));
    return Eigen::Vector3d(base + 27.8 * (flipped ? u1 : u2));
  };
  Output out;
  HindsightSwaps repair(options, [&](uint64_t, const std::vector<TrackSample>& row) {
    for (const TrackSample& s : row) out[s.frame_number][s.marker] = s.position;
  });
  for (int f = 0; f < frames; ++f) {
    std::vector<TrackSample> samples;
    for (int marker = 0; marker < 3; ++marker) {
      TrackSample s;
      s.marker = marker == 0 || !traded(f) ? marker : 3 - marker;
      s.frame_number = static_cast<uint64_t>(f);
      s.position = at(marker, f) + Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
      samples.push_back(s);
    }
    repair.Add(static_cast<uint64_t>(f), samples);
  }
  repair.Finish();
  *undone = repair.swaps_undone();
  for (auto& [frame, columns] : out) {
    for (auto& [marker, position] : columns) position -= at(marker, static_cast<int>(frame));
  }
  return out;
}

void ExpectOwnMarkers(const Output& miss, int frames) {
  ASSERT_EQ(miss.size(), static_cast<size_t>(frames));
  for (const auto& [frame, columns] : miss) {
    for (const auto& [marker, offset] : columns) EXPECT_LT(offset.norm(), 2.0) << frame << " " << marker;
  }
}

TEST(HindsightSwaps, RigidClusterKeepsItsLabelsWhereItsMarkersJump) {
  long long undone = 0;
  const auto as_tracked = [](int) { return false; };
  ExpectOwnMarkers(RunFlippingCluster(HindsightSwapOptions(), 140, 90, as_tracked, &undone), 140);
  EXPECT_EQ(undone, 0);
  // Smoothness alone trades them: the scene tells the two apart.
  HindsightSwapOptions smooth_only;
  smooth_only.rigid_weight = 0.0;
  const Output miss = RunFlippingCluster(smooth_only, 140, 90, as_tracked, &undone);
  EXPECT_EQ(undone, 1);
  EXPECT_GT(miss.at(100).at(1).norm(), 5.0);
}

TEST(HindsightSwaps, SmoothTradeThatBendsARigidClusterIsUndone) {
  long long undone = 0;
  const auto smooth = [](int f) { return f >= 90; };  // the tracker followed the nearest points
  ExpectOwnMarkers(RunFlippingCluster(HindsightSwapOptions(), 140, 90, smooth, &undone), 140);
  EXPECT_EQ(undone, 1);
  HindsightSwapOptions smooth_only;
  smooth_only.rigid_weight = 0.0;
  const Output miss = RunFlippingCluster(smooth_only, 140, 90, smooth, &undone);
  EXPECT_EQ(undone, 0);
  EXPECT_GT(miss.at(100).at(1).norm(), 5.0);
}

// A rigid cluster of three markers (0 the base, 1 and 2 at 18.6 and 27.8 mm) whose marker 1's
// track is lost after frame 59; the tracker's new marker 3 takes it up from frame 62, confirmed
// at 64 with its first frames back-filled. `offset` is added to marker 3's points; `comeback`:
// the lost track is found again at frame 80 while marker 3 goes on.
struct JoinRun {
  std::map<uint64_t, std::map<int, Eigen::Vector3d>> out;  // frame -> column -> miss
  long long joined = 0;
};

JoinRun RunLostMarker(const Eigen::Vector3d& offset, bool comeback) {
  const auto at = [](int marker, int f) {
    const Eigen::Vector3d base(4.0 * f, 100.0 + 15.0 * std::sin(f / 25.0), 0.0);
    const double phi = 0.01 * f;
    if (marker == 0) return base;
    if (marker == 1) return Eigen::Vector3d(base + 18.6 * Eigen::Vector3d(std::cos(phi), std::sin(phi), 0.0));
    return Eigen::Vector3d(base + 27.8 * Eigen::Vector3d(-std::sin(phi), std::cos(phi), 0.0));
  };
  JoinRun run;
  // Which true marker each of the tracker's markers follows.
  std::map<int, int> true_of_column;
  HindsightSwaps repair(HindsightSwapOptions(), [&](uint64_t, const std::vector<TrackSample>& row) {
    for (const TrackSample& s : row) {
      EXPECT_EQ(run.out[s.frame_number].count(s.marker), 0u) << "frame " << s.frame_number;
      run.out[s.frame_number][s.marker] = s.position;
    }
  });
  const auto sample = [&](int tracker_marker, int true_marker, int f) {
    TrackSample s;
    s.marker = tracker_marker;
    s.frame_number = static_cast<uint64_t>(f);
    s.position = at(true_marker, f) + (tracker_marker == 3 ? offset : Eigen::Vector3d::Zero());
    return s;
  };
  for (int f = 0; f < 120; ++f) {
    std::vector<TrackSample> samples{sample(0, 0, f), sample(2, 2, f)};
    if (f < 60 || (comeback && f >= 80)) samples.push_back(sample(1, 1, f));
    if (f == 64) {
      for (int back = 62; back <= 64; ++back) samples.push_back(sample(3, 1, back));
    } else if (f > 64) {
      samples.push_back(sample(3, 1, f));
    }
    repair.Add(static_cast<uint64_t>(f), samples);
  }
  repair.Finish();
  run.joined = repair.columns_joined();
  for (auto& [frame, columns] : run.out) {
    for (auto& [column, position] : columns) {
      // Columns 0-2 are the markers'; a new column follows marker 1.
      position -= at(column <= 2 ? column : 1, static_cast<int>(frame));
    }
  }
  return run;
}

TEST(HindsightSwaps, NewTrackThatFitsALostMarkersClusterContinuesItsColumn) {
  const JoinRun run = RunLostMarker(Eigen::Vector3d::Zero(), false);
  EXPECT_EQ(run.joined, 1);
  for (const auto& [frame, columns] : run.out) {
    EXPECT_EQ(columns.size(), frame >= 60 && frame < 62 ? 2u : 3u) << frame;
    for (const auto& [column, miss] : columns) {
      EXPECT_LE(column, 2) << frame;
      EXPECT_LT(miss.norm(), 1e-9) << frame << " " << column;
    }
  }
}

TEST(HindsightSwaps, NewTrackThatBendsTheClusterGetsItsOwnColumn) {
  const JoinRun run = RunLostMarker(Eigen::Vector3d(0.0, 0.0, 25.0), false);
  EXPECT_EQ(run.joined, 0);
  EXPECT_EQ(run.out.at(70).count(1), 0u);
  EXPECT_EQ(run.out.at(70).count(3), 1u);
}

TEST(HindsightSwaps, LostTrackFoundAgainAfterAJoinTakesAColumnOfItsOwn) {
  const JoinRun run = RunLostMarker(Eigen::Vector3d::Zero(), true);  // the sink checks duplicates
  EXPECT_EQ(run.joined, 1);
  EXPECT_EQ(run.out.at(90).size(), 4u);
  EXPECT_EQ(run.out.at(90).count(3), 1u);
}

TEST(HindsightSwaps, LateSamplesAndPausesPassThrough) {
  std::map<uint64_t, int> samples_of_frame;
  uint64_t last_sent = 0;
  HindsightSwaps repair(HindsightSwapOptions(), [&](uint64_t frame, const std::vector<TrackSample>& row) {
    EXPECT_GE(frame, last_sent);
    last_sent = frame;
    for (const TrackSample& s : row) ++samples_of_frame[s.frame_number];
  });
  for (uint64_t f = 0; f < 30; ++f) {
    const uint64_t frame = f < 25 ? f : f + 100;  // a pause of 100 frames after frame 24
    std::vector<TrackSample> samples(1);
    samples[0].frame_number = frame;
    if (f == 20) {
      // A track confirmed now: its first frames come late, under a new marker.
      for (uint64_t back = 2; back <= 12; ++back) {
        TrackSample s;
        s.marker = 1;
        s.frame_number = f - back;
        samples.push_back(s);
      }
    }
    repair.Add(frame, samples);
  }
  repair.Finish();
  EXPECT_EQ(samples_of_frame.size(), 30u);
  for (uint64_t f = 8; f <= 18; ++f) EXPECT_EQ(samples_of_frame[f], 2) << f;
  EXPECT_THROW(HindsightSwaps(HindsightSwapOptions{true, 0.0, 0.25, 6.0}, nullptr), std::invalid_argument);
}

}  // namespace
}  // namespace mocap
