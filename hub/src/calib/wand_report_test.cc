// The wand report's figures from a real solve (each camera rated, residual and coverage figures
// that add up to the observations used, a layout with z up), and its HTML page: self-contained,
// the figures embedded so that no text in them can end the script element.
#include "calib/wand_report.h"

#include <gtest/gtest.h>

#include "simcore/test_scenes.h"

namespace mocap {
namespace {

class WandReportTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    truth_ = new Rig(testing::RingRig(5, 31));
    const WandGeometry wand = WandGeometry::TwoMarker(500.0);
    const testing::WandScene scene = testing::MakeWandScene(*truth_, wand.marker_offsets_mm, 800, 0.15, 32);
    result_ = new WandCalibrationResult(CalibrateWand(scene.frames, *truth_, wand, WandCalibrationOptions()));
  }
  static void TearDownTestSuite() {
    delete result_;
    delete truth_;
  }
  static Rig* truth_;
  static WandCalibrationResult* result_;
};

Rig* WandReportTest::truth_ = nullptr;
WandCalibrationResult* WandReportTest::result_ = nullptr;

TEST_F(WandReportTest, FiguresRateEveryCameraAndAddUp) {
  ASSERT_TRUE(result_->AllAccepted());
  const nlohmann::json f = WandReportFigures(*result_, WandGeometry::TwoMarker(500.0), RatingThresholds(), "t");
  ASSERT_EQ(f["cameras"].size(), 5u);
  size_t observations = 0;
  for (const auto& c : f["cameras"]) {
    EXPECT_NE(c["rating"].get<std::string>(), "Poor") << c.dump();
    const auto& r = c["residuals"];
    observations += r["observations"].get<size_t>();
    size_t binned = 0;
    for (const auto& n : r["histogram"]["counts"]) binned += n.get<size_t>();
    EXPECT_EQ(binned, r["observations"].get<size_t>());  // nothing lost off the ends
    EXPECT_LE(r["p50_px"].get<double>(), r["p95_px"].get<double>());
    // Two markers per view, every sighting in one cell of the map.
    size_t sightings = 0;
    for (const auto& n : c["coverage_map"]["counts"]) sightings += n.get<size_t>();
    EXPECT_EQ(sightings, 2 * c["views_used"].get<size_t>());
    EXPECT_EQ(c["coverage_map"]["counts"].size(),
              c["coverage_map"]["columns"].get<size_t>() * c["coverage_map"]["rows"].get<size_t>());
    ASSERT_TRUE(c.contains("position"));
  }
  EXPECT_GT(observations, 1000u);
  size_t frames = 0;
  for (const auto& n : f["wand_length_histogram"]["counts"]) frames += n.get<size_t>();
  EXPECT_EQ(frames, result_->frames_used);
  EXPECT_EQ(f["rating_thresholds"]["reprojection_rms_px"]["Exceptional"].get<double>(), 0.2);
  // The ring's cameras stand above the volume they look at: in the plot frame (z up) every
  // camera looks down.
  for (const auto& c : f["cameras"]) EXPECT_LT(c["direction"][2].get<double>(), 0.0) << c.dump();
  EXPECT_FALSE(f["layout"]["wand_centres"].empty());
}

TEST_F(WandReportTest, HtmlEmbedsTheFiguresAndThePlottingModule) {
  nlohmann::json f = WandReportFigures(*result_, WandGeometry::TwoMarker(500.0), RatingThresholds(),
                                       "</script><b>x</b>");
  const std::string html = WandReportHtml(f);
  EXPECT_EQ(html.rfind("<!doctype html>", 0), 0u);
  EXPECT_NE(html.find("function renderWandReport"), std::string::npos);
  // The title cannot close the data's script element nor add markup.
  EXPECT_EQ(html.find("</script><b>"), std::string::npos);
  EXPECT_EQ(html.find("<b>x"), std::string::npos);
  const size_t open = html.find("id=\"figures\">");
  ASSERT_NE(open, std::string::npos);
  const size_t start = open + 13;
  const size_t end = html.find("</script>", start);
  const nlohmann::json back = nlohmann::json::parse(html.substr(start, end - start));
  EXPECT_EQ(back, f);
}

TEST_F(WandReportTest, CalibrationDocumentCarriesTheReport) {
  const nlohmann::json report = WandResultJson(*result_, WandGeometry::TwoMarker(500.0), RatingThresholds());
  const nlohmann::json document = WandCalibrationDocument(*result_, report);
  ASSERT_EQ(document["cameras"].size(), 5u);
  EXPECT_TRUE(document["cameras"][0].contains("reprojection_rms_px"));
  EXPECT_EQ(document["calibration"]["rating"], report["rating"]);
}

}  // namespace
}  // namespace mocap
