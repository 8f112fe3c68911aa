// The five fill methods on a rigid segment with known truth: each fills a cut gap close to the
// truth (donor methods near exactly, since the segment is rigid), marks what it filled with its
// method, leaves measured samples alone, and leaves what it cannot fill as gaps.
#include "edit/gap_fill.h"

#include <gtest/gtest.h>

#include "edit/edit_testing.h"

namespace mocap::edit {
namespace {

using testing::SegmentPoint;
using testing::SegmentTake;

void Cut(EditedTake* take, size_t marker, size_t first, size_t last) {
  for (size_t f = first; f <= last; ++f) take->Clear(f, marker);
}

double MaxError(const EditedTake& take, size_t marker, size_t first, size_t last) {
  double worst = 0.0;
  for (size_t f = first; f <= last; ++f) {
    if (!take.markers.Has(f, marker)) return 1e9;
    worst = std::max(worst, (take.markers.At(f, marker) - SegmentPoint(marker, f / take.markers.rate_hz)).norm());
  }
  return worst;
}

struct Case {
  FillMethod method;
  std::vector<size_t> donors;
  double max_error_mm;  // over a 0.2 s gap of a marker moving up to ~1 m/s
};

TEST(GapFill, EachMethodFillsACutGapNearTheTruthAndMarksIt) {
  const Case cases[] = {{FillMethod::kSpline, {}, 3.0},        {FillMethod::kLinear, {}, 30.0},
                        {FillMethod::kPattern, {0}, 30.0},     {FillMethod::kRigid, {0, 1, 2}, 1e-6},
                        {FillMethod::kRelational, {0, 1, 2}, 1e-6}};
  for (const Case& c : cases) {
    EditedTake take = SegmentTake(300);
    const EditedTake before = take;
    Cut(&take, 3, 100, 119);
    FillOptions options;
    options.method = c.method;
    options.donors = c.donors;
    const FillResult r = FillGaps(&take, 3, 0, 299, options);
    SCOPED_TRACE(FillMethodName(c.method));
    EXPECT_EQ(r.gaps_seen, 1u);
    EXPECT_EQ(r.gaps_filled, 1u);
    EXPECT_EQ(r.samples_filled, 20u);
    EXPECT_EQ(r.samples_left, 0u);
    EXPECT_LT(MaxError(take, 3, 100, 119), c.max_error_mm);
    for (size_t f = 0; f < 300; ++f) {
      const bool in_gap = f >= 100 && f <= 119;
      EXPECT_EQ(take.Mark(f, 3), in_gap ? static_cast<uint8_t>(c.method) : 0) << f;
      if (!in_gap) {
        EXPECT_EQ(take.markers.At(f, 3), before.markers.At(f, 3)) << f;
      }
    }
  }
}

TEST(GapFill, SplineBeatsLinearOnACurvedPath) {
  EditedTake spline = SegmentTake(300);
  Cut(&spline, 3, 100, 129);
  EditedTake linear = spline;
  FillOptions options;
  FillGaps(&spline, 3, 0, 299, options);
  options.method = FillMethod::kLinear;
  FillGaps(&linear, 3, 0, 299, options);
  EXPECT_LT(MaxError(spline, 3, 100, 129), 0.5 * MaxError(linear, 3, 100, 129));
}

TEST(GapFill, InterpolationNeedsBothEndsDonorsNeedOne) {
  EditedTake take = SegmentTake(200);
  Cut(&take, 3, 0, 9);      // at the start
  Cut(&take, 3, 190, 199);  // at the end
  EditedTake rigid = take;
  FillOptions options;
  const FillResult r = FillGaps(&take, 3, 0, 199, options);
  EXPECT_EQ(r.gaps_seen, 2u);
  EXPECT_EQ(r.gaps_filled, 0u);
  EXPECT_EQ(r.samples_left, 20u);
  EXPECT_FALSE(take.markers.Has(5, 3));
  options.method = FillMethod::kRigid;
  options.donors = {0, 1, 2};
  const FillResult rr = FillGaps(&rigid, 3, 0, 199, options);
  EXPECT_EQ(rr.gaps_filled, 2u);
  EXPECT_LT(MaxError(rigid, 3, 0, 9), 1e-6);
  EXPECT_LT(MaxError(rigid, 3, 190, 199), 1e-6);
}

TEST(GapFill, AFrameWithoutItsDonorsStaysAGap) {
  EditedTake take = SegmentTake(200);
  Cut(&take, 3, 50, 69);
  take.Clear(60, 1);
  FillOptions options;
  options.method = FillMethod::kRelational;
  options.donors = {0, 1, 2};
  const FillResult r = FillGaps(&take, 3, 0, 199, options);
  EXPECT_EQ(r.samples_filled, 19u);
  EXPECT_EQ(r.samples_left, 1u);
  EXPECT_EQ(r.gaps_filled, 0u);
  EXPECT_FALSE(take.markers.Has(60, 3));
  EXPECT_EQ(take.Mark(60, 3), 0);
}

TEST(GapFill, RangeAndMaxGapChooseTheGaps) {
  EditedTake take = SegmentTake(300);
  Cut(&take, 3, 20, 24);
  Cut(&take, 3, 100, 139);
  Cut(&take, 3, 200, 204);
  FillOptions options;
  options.max_gap = 10;
  const FillResult r = FillGaps(&take, 3, 0, 150, options);  // the third gap is outside
  EXPECT_EQ(r.gaps_seen, 2u);
  EXPECT_EQ(r.gaps_filled, 1u);
  EXPECT_TRUE(take.markers.Has(22, 3));
  EXPECT_FALSE(take.markers.Has(120, 3));
  EXPECT_FALSE(take.markers.Has(202, 3));
}

TEST(GapFill, SkippedFrameNumbersAreTime) {
  // Every other frame number missing from the file: the spline must still place samples at
  // their frame numbers' instants.
  EditedTake dense = SegmentTake(400);
  MarkerTrajectories m;
  m.rate_hz = dense.markers.rate_hz;
  m.names = dense.markers.names;
  for (size_t f = 0; f < 400; f += 2) {
    const size_t i = m.AddFrame(dense.markers.frame_numbers[f]);
    for (size_t c = 0; c < 4; ++c) m.At(i, c) = dense.markers.At(f, c);
  }
  EditedTake take = EditedTake::FromMeasured(std::move(m));
  for (size_t i = 50; i < 60; ++i) take.Clear(i, 3);
  FillGaps(&take, 3, 0, 199, FillOptions{});
  for (size_t i = 50; i < 60; ++i)
    EXPECT_LT((take.markers.At(i, 3) - SegmentPoint(3, (take.markers.frame_numbers[i] - 1000) / 100.0)).norm(), 3.0);
}

TEST(GapFill, OptionsAreChecked) {
  FillOptions o;
  o.context = 1;
  EXPECT_THROW(o.Check(), std::invalid_argument);
  o = FillOptions{};
  o.donors = {1};
  EXPECT_THROW(o.Check(), std::invalid_argument);  // spline takes none
  o.method = FillMethod::kPattern;
  EXPECT_NO_THROW(o.Check());
  o.method = FillMethod::kRigid;
  EXPECT_THROW(o.Check(), std::invalid_argument);
  o.method = FillMethod::kRelational;
  o.donors = {0, 1, 2, 3};
  EXPECT_THROW(o.Check(), std::invalid_argument);
  EditedTake take = SegmentTake(50);
  o.donors = {3, 1, 2};
  EXPECT_THROW(FillGaps(&take, 3, 0, 49, o), std::invalid_argument);  // its own donor
}

}  // namespace
}  // namespace mocap::edit
