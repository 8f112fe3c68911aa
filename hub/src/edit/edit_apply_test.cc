// The edit operations applied through a log: what each does to samples and fill marks, the
// refusals that name the operation, spikes found and removed, and the files written (the side
// file's stretches, the C3D residual words read back).
#include "edit/edit_apply.h"

#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "edit/edit_output.h"
#include "edit/edit_testing.h"
#include "io/c3d.h"
#include "io/trc.h"

namespace mocap::edit {
namespace {

using testing::SegmentTake;

EditReport Apply(const std::string& operations, EditedTake* take) {
  return ApplyEdits(ParseEditLog(R"({"format": "mocap-edits", "version": 1, "operations": )" + operations + "}", "test"),
                    take);
}

std::string Refusal(const std::string& operations, EditedTake take) {
  try {
    Apply(operations, &take);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(EditApply, SwapExchangesSamplesAndMarksOverTheRangeOnly) {
  EditedTake take = SegmentTake(100);
  const EditedTake before = take;
  take.marks[10 * 4 + 0] = static_cast<uint8_t>(FillMethod::kLinear);
  Apply(R"([{"op": "swap", "markers": ["A", "B"], "from": 1010, "to": 1019}])", &take);
  for (size_t f = 0; f < 100; ++f) {
    const bool in = f >= 10 && f <= 19;
    EXPECT_EQ(take.markers.At(f, 0), before.markers.At(f, in ? 1 : 0));
    EXPECT_EQ(take.markers.At(f, 1), before.markers.At(f, in ? 0 : 1));
  }
  EXPECT_EQ(take.Mark(10, 1), static_cast<uint8_t>(FillMethod::kLinear));
  EXPECT_EQ(take.Mark(10, 0), 0);
}

TEST(EditApply, SplitThenJoinRestoresTheColumn) {
  EditedTake take = SegmentTake(100);
  const EditedTake before = take;
  const EditReport r = Apply(R"([{"op": "split", "marker": "C", "frame": 1040, "name": "C2"}])", &take);
  ASSERT_EQ(take.markers.NumMarkers(), 5u);
  EXPECT_EQ(take.markers.names[4], "C2");
  EXPECT_TRUE(take.markers.Has(39, 2));
  EXPECT_FALSE(take.markers.Has(40, 2));
  EXPECT_FALSE(take.markers.Has(39, 4));
  EXPECT_EQ(take.markers.At(40, 4), before.markers.At(40, 2));
  EXPECT_NE(r.lines[0].find("60 samples moved"), std::string::npos) << r.lines[0];
  Apply(R"([{"op": "join", "marker": "C", "other": "C2"}])", &take);
  EXPECT_EQ(take.markers.names, before.markers.names);
  EXPECT_EQ(take.markers.points, before.markers.points);
}

TEST(EditApply, JoinRefusesOverlapRenameRefusesATakenName) {
  const EditedTake take = SegmentTake(50);
  const std::string overlap = Refusal(R"([{"op": "join", "marker": "A", "other": "B"}])", take);
  EXPECT_NE(overlap.find("operation 1 (join)"), std::string::npos) << overlap;
  EXPECT_NE(overlap.find("50 frames, the first 1000"), std::string::npos) << overlap;
  const std::string taken = Refusal(R"([{"op": "rename", "marker": "A", "name": "B"}])", take);
  EXPECT_NE(taken.find("'B' is already"), std::string::npos) << taken;
  const std::string missing =
      Refusal(R"([{"op": "rename", "marker": "A", "name": "Z"}, {"op": "delete", "marker": "A"}])", take);
  EXPECT_NE(missing.find("operation 2 (delete): marker 'A' is not in the take"), std::string::npos) << missing;
  const std::string donor =
      Refusal(R"([{"op": "fill", "marker": "A", "method": "rigid", "donors": ["B", "C"]}])", take);
  EXPECT_NE(donor.find("three or more donors"), std::string::npos) << donor;
}

TEST(EditApply, DeleteARangeOrTheColumn) {
  EditedTake take = SegmentTake(50);
  Apply(R"([{"op": "delete", "marker": "B", "from": 1005, "to": 1009}, {"op": "rename", "marker": "D", "name": "RKNE"},
            {"op": "delete", "marker": "A"}])",
        &take);
  EXPECT_EQ(take.markers.names, (std::vector<std::string>{"B", "C", "RKNE"}));
  EXPECT_TRUE(take.markers.Has(4, 0));
  EXPECT_FALSE(take.markers.Has(5, 0));
  EXPECT_FALSE(take.markers.Has(9, 0));
  EXPECT_TRUE(take.markers.Has(10, 0));
  EXPECT_EQ(take.marks.size(), take.markers.points.size());
}

TEST(EditApply, SpikesAreFoundAtTheirFrameAndRemovedThenFilled) {
  EditedTake take = SegmentTake(300);
  const EditedTake clean = take;
  take.markers.At(77, 2) += Eigen::Vector3d(0, 0, 25);
  take.markers.At(201, 0) += Eigen::Vector3d(12, -9, 0);
  const EditReport found = Apply(R"([{"op": "spikes"}])", &take);
  ASSERT_EQ(found.spikes.size(), 2u);
  EXPECT_EQ(found.spikes[0].marker, "A");
  EXPECT_EQ(found.spikes[0].frame, 1201u);
  EXPECT_EQ(found.spikes[1].marker, "C");
  EXPECT_EQ(found.spikes[1].frame, 1077u);
  EXPECT_TRUE(take.markers.Has(77, 2));  // reported only
  Apply(R"([{"op": "spikes", "remove": true}, {"op": "fill", "marker": "C", "method": "spline"},
            {"op": "fill", "marker": "A", "method": "spline"}])",
        &take);
  EXPECT_LT((take.markers.At(77, 2) - clean.markers.At(77, 2)).norm(), 0.5);
  EXPECT_LT((take.markers.At(201, 0) - clean.markers.At(201, 0)).norm(), 0.5);
  EXPECT_EQ(take.Mark(77, 2), static_cast<uint8_t>(FillMethod::kSpline));
  EditedTake smooth = clean;
  EXPECT_TRUE(Apply(R"([{"op": "spikes"}])", &smooth).spikes.empty());
}

TEST(EditApply, TheOutputsSayWhichSamplesWereFilled) {
  EditedTake take = SegmentTake(60);
  for (size_t f = 20; f < 30; ++f) take.Clear(f, 1);
  take.Clear(45, 3);
  Apply(R"([{"op": "fill", "marker": "B", "method": "rigid", "donors": ["A", "C", "D"], "from": 1000, "to": 1025}])",
        &take);
  const std::string dir = ::testing::TempDir();
  WriteEditedTake(take, dir + "/edited.c3d");
  WriteEditedTake(take, dir + "/edited.trc");
  EXPECT_EQ(FilledSidePath(dir + "/edited.c3d"), dir + "/edited.filled.tsv");
  std::ifstream side(dir + "/edited.filled.tsv");
  std::stringstream text;
  text << side.rdbuf();
  EXPECT_NE(text.str().find("marker\tfirst_frame\tlast_frame\tmethod\nB\t1020\t1029\trigid\n"), std::string::npos)
      << text.str();
  std::vector<float> residuals;
  const MarkerTrajectories c3d = ReadC3d(dir + "/edited.c3d", &residuals);
  ASSERT_EQ(residuals.size(), 60u * 4u);
  for (size_t f = 0; f < 60; ++f)
    for (size_t c = 0; c < 4; ++c) {
      const float expected = (c == 1 && f >= 20 && f < 30) ? 0.0f : (c == 3 && f == 45) ? -1.0f : kMeasuredResidual;
      EXPECT_EQ(residuals[f * 4 + c], expected) << f << " " << c;
    }
  const MarkerTrajectories trc = ReadTrc(dir + "/edited.trc");
  EXPECT_TRUE(trc.Has(25, 1));
  EXPECT_FALSE(trc.Has(45, 3));
}

TEST(EditApply, FrameNumbersMustIncrease) {
  EditedTake take = SegmentTake(10);
  take.markers.frame_numbers[5] = 1002;
  EXPECT_THROW(Apply("[]", &take), std::invalid_argument);
}

}  // namespace
}  // namespace mocap::edit
