// The API's request surface without a network: each route reaches the right service call with
// the right values, and every bad request is refused with the status and a reason.
#include "service/api_router.h"

#include <gtest/gtest.h>

#include "service/fake_service_api.h"

namespace mocap::service {
namespace {

struct Routed {
  ApiResponse response;
  nlohmann::json body;
};

Routed Send(FakeServiceApi& api, const std::string& method, const std::string& path, const std::string& body = "",
            const std::string& query = "") {
  Routed r;
  r.response = HandleApiRequest(api, {method, path, query, body});
  if (r.response.content_type == "application/json") r.body = nlohmann::json::parse(r.response.body);
  return r;
}

TEST(ApiRouter, RoutesReachTheirCalls) {
  FakeServiceApi api;
  EXPECT_EQ(Send(api, "GET", "/api/status").body["called"], "status");
  EXPECT_EQ(Send(api, "GET", "/api/nodes").body["called"], "nodes");
  EXPECT_EQ(Send(api, "GET", "/api/nodes/1/").body["called"], "node");
  EXPECT_EQ(Send(api, "POST", "/api/capture/start", R"({"name": "take 1"})").body["called"], "start");
  EXPECT_EQ(api.last_name, "take 1");  // the service judges names (capture_test)
  EXPECT_EQ(Send(api, "POST", "/api/capture/stop").body["called"], "stop");
  EXPECT_EQ(Send(api, "GET", "/api/sessions").body["called"], "sessions");
  EXPECT_EQ(Send(api, "DELETE", "/api/masks").body["called"], "clearmasks");
  EXPECT_EQ(Send(api, "POST", "/api/masks/auto", "").body["called"], "automask");
  EXPECT_EQ(api.last_number, 100u);
  Send(api, "POST", "/api/masks/auto", R"({"frames": 250})");
  EXPECT_EQ(api.last_number, 250u);
}

TEST(ApiRouter, SettingsCarryExactlyWhatWasGiven) {
  FakeServiceApi api;
  ASSERT_EQ(Send(api, "POST", "/api/nodes/1/settings", R"({"threshold": 40, "gain_milli": 2000})").response.status, 200);
  EXPECT_EQ(api.last_node, 1u);
  EXPECT_EQ(api.last_settings.threshold.value_or(0), 40u);
  EXPECT_EQ(api.last_settings.gain_milli.value_or(0), 2000u);
  EXPECT_FALSE(api.last_settings.exposure_us.has_value());
  EXPECT_FALSE(api.last_settings.auto_threshold);
  ASSERT_EQ(Send(api, "POST", "/api/nodes/1/settings", R"({"brightness_pct": 0, "contrast_pct": 65})").response.status,
            200);
  EXPECT_EQ(api.last_settings.brightness_pct.value_or(99), 0u);
  EXPECT_EQ(api.last_settings.contrast_pct.value_or(0), 65u);
  ASSERT_EQ(Send(api, "POST", "/api/nodes/1/settings", R"({"auto_threshold": true})").response.status, 200);
  EXPECT_TRUE(api.last_settings.auto_threshold);
  EXPECT_FALSE(api.last_settings.threshold.has_value());
}

TEST(ApiRouter, PreviewIsAPngWithItsQuery) {
  FakeServiceApi api;
  const Routed r = Send(api, "GET", "/api/nodes/1/preview", "", "mode=thresholded&downscale=4");
  EXPECT_EQ(r.response.status, 200);
  EXPECT_EQ(r.response.content_type, "image/png");
  EXPECT_EQ(r.response.body.substr(1, 3), "PNG");
  EXPECT_TRUE(api.last_thresholded);
  EXPECT_EQ(api.last_number, 4u);
  Send(api, "GET", "/api/nodes/1/preview");
  EXPECT_FALSE(api.last_thresholded);
  EXPECT_EQ(api.last_number, 2u);
}

TEST(ApiRouter, BadRequestsAreRefusedWithTheirStatusAndAReason) {
  struct Case {
    const char *method, *path, *body, *query;
    int status;
  };
  const Case cases[] = {
      {"GET", "/api/nowhere", "", "", 404},
      {"GET", "/", "", "", 404},
      {"GET", "/api/nodes/0", "", "", 404},
      {"GET", "/api/nodes/99999999999", "", "", 404},
      {"GET", "/api/nodes/-3", "", "", 404},
      {"GET", "/api/nodes/7", "", "", 404},  // the service does not know it
      {"GET", "/api/nodes/1/reboot", "", "", 404},
      {"POST", "/api/status", "", "", 405},
      {"GET", "/api/capture/start", "", "", 405},
      {"POST", "/api/nodes/1/settings", "{", "", 400},
      {"POST", "/api/nodes/1/settings", "[1]", "", 400},
      {"POST", "/api/nodes/1/settings", "{}", "", 400},
      {"POST", "/api/nodes/1/settings", R"({"threshold": 0})", "", 400},
      {"POST", "/api/nodes/1/settings", R"({"threshold": 256})", "", 400},
      {"POST", "/api/nodes/1/settings", R"({"threshold": 4.5})", "", 400},
      {"POST", "/api/nodes/1/settings", R"({"threshold": "40"})", "", 400},
      {"POST", "/api/nodes/1/settings", R"({"threshold": 18446744073709551615})", "", 400},
      {"POST", "/api/nodes/1/settings", R"({"threshold": 40, "auto_threshold": true})", "", 400},
      {"POST", "/api/nodes/1/settings", R"({"auto_threshold": 1})", "", 400},
      {"POST", "/api/nodes/1/settings", R"({"exposure_us": 2000000})", "", 400},
      {"POST", "/api/nodes/1/settings", R"({"brightness_pct": 101})", "", 400},
      {"POST", "/api/nodes/1/settings", R"({"contrast_pct": -1})", "", 400},
      {"POST", "/api/nodes/1/settings", R"({"colour": "red"})", "", 400},
      {"POST", "/api/nodes/1/identify", R"({"duration_ms": 5})", "", 400},
      {"GET", "/api/nodes/1/preview", "", "mode=colour", 400},
      {"GET", "/api/nodes/1/preview", "", "downscale=3", 400},
      {"GET", "/api/nodes/1/preview", "", "zoom=2", 400},
      {"POST", "/api/masks/auto", R"({"frames": 5})", "", 400},
      {"POST", "/api/capture/start", "{}", "", 400},
      {"POST", "/api/capture/start", R"({"name": 5})", "", 400},
      {"POST", "/api/capture/stop", R"({"now": true})", "", 400},
  };
  for (const Case& c : cases) {
    FakeServiceApi api;
    const Routed r = Send(api, c.method, c.path, c.body, c.query);
    EXPECT_EQ(r.response.status, c.status) << c.method << " " << c.path << " " << c.body << " " << c.query;
    ASSERT_TRUE(r.body.contains("error")) << r.response.body;
    EXPECT_FALSE(r.body["error"].get<std::string>().empty());
    // A refused value never reaches the service (unknown nodes are the service's to judge).
    if (c.status == 400) {
      EXPECT_TRUE(api.calls.empty()) << c.path << " " << c.body;
    }
  }
}

TEST(ApiRouter, SessionsCalibrationAndBlobs) {
  FakeServiceApi api;
  EXPECT_EQ(Send(api, "GET", "/api/calibration").body["called"], "calibration");
  EXPECT_EQ(Send(api, "GET", "/api/blobs").body["called"], "blobs");
  EXPECT_EQ(Send(api, "GET", "/api/sessions/walk_01").body["called"], "session");
  EXPECT_EQ(api.last_name, "walk_01");
  const Routed trc = Send(api, "GET", "/api/sessions/walk_01/files/markers.trc");
  EXPECT_EQ(trc.response.status, 200);
  EXPECT_EQ(trc.response.file, "/sessions/walk_01/markers.trc");
  EXPECT_EQ(trc.response.content_type, "text/plain; charset=utf-8");
  EXPECT_EQ(api.last_name, "walk_01/markers.trc");
  EXPECT_EQ(Send(api, "GET", "/api/sessions/walk_01/files/markers.c3d").response.content_type,
            "application/octet-stream");
  EXPECT_EQ(Send(api, "GET", "/api/sessions/walk_01/files/live_points.tsv").response.content_type,
            "text/tab-separated-values; charset=utf-8");
}

TEST(ApiRouter, ProcessingASessionAndItsResults) {
  FakeServiceApi api;
  const Routed queued = Send(api, "POST", "/api/sessions/walk_01/process", R"({"recipe": {"name": "gait"}})");
  EXPECT_EQ(queued.response.status, 202);
  EXPECT_EQ(queued.body["called"], "process");
  EXPECT_EQ(api.last_name, "walk_01");
  EXPECT_EQ(api.last_request["recipe"]["name"], "gait");
  EXPECT_EQ(Send(api, "GET", "/api/processing").body["called"], "processing");
  const Routed file = Send(api, "GET", "/api/sessions/walk_01/processed/gait/files/markers.c3d");
  EXPECT_EQ(file.response.status, 200);
  EXPECT_EQ(file.response.file, "/sessions/walk_01/processed/gait/markers.c3d");
  EXPECT_EQ(file.response.content_type, "application/octet-stream");
  // A misspelt field, a wrong method, a name that could leave the directory: refused here.
  FakeServiceApi other;
  EXPECT_EQ(Send(other, "POST", "/api/sessions/walk_01/process", R"({"recipes": {}})").response.status, 400);
  EXPECT_EQ(Send(other, "GET", "/api/sessions/walk_01/process").response.status, 405);
  EXPECT_EQ(Send(other, "POST", "/api/processing").response.status, 405);
  EXPECT_EQ(Send(other, "GET", "/api/sessions/walk_01/processed/../files/x").response.status, 404);
  EXPECT_EQ(Send(other, "GET", "/api/sessions/walk_01/processed/gait/files/.hidden").response.status, 404);
  EXPECT_EQ(Send(other, "GET", "/api/sessions/walk_01/processed/gait/other/x").response.status, 404);
  EXPECT_TRUE(other.calls.empty());
}

TEST(ApiRouter, SessionsAreDeletedRenamedAndAnnotated) {
  FakeServiceApi api;
  EXPECT_EQ(Send(api, "DELETE", "/api/sessions/walk_01").body["called"], "deletesession");
  EXPECT_EQ(api.last_name, "walk_01");
  EXPECT_EQ(Send(api, "POST", "/api/sessions/walk_01/rename", R"({"name": "walk_02"})").body["called"],
            "renamesession");
  EXPECT_EQ(api.last_name, "walk_01>walk_02");
  EXPECT_EQ(Send(api, "PUT", "/api/sessions/walk_01/notes", R"({"notes": "subject 3, left knee brace"})").body["called"],
            "annotatesession");
  EXPECT_EQ(api.last_name, "walk_01:subject 3, left knee brace");
  FakeServiceApi other;
  EXPECT_EQ(Send(other, "POST", "/api/sessions/walk_01/rename", R"({"to": "x"})").response.status, 400);
  EXPECT_EQ(Send(other, "POST", "/api/sessions/walk_01/rename", R"({"name": 7})").response.status, 400);
  EXPECT_EQ(Send(other, "GET", "/api/sessions/walk_01/rename").response.status, 405);
  EXPECT_EQ(Send(other, "POST", "/api/sessions/walk_01/notes", R"({"notes": ""})").response.status, 405);
  EXPECT_EQ(Send(other, "PUT", "/api/sessions/walk_01/notes", R"({"notes": null})").response.status, 400);
  EXPECT_EQ(Send(other, "DELETE", "/api/sessions/..").response.status, 404);
  EXPECT_TRUE(other.calls.empty());
}

TEST(ApiRouter, TheEditLogOfResults) {
  FakeServiceApi api;
  EXPECT_EQ(Send(api, "GET", "/api/sessions/walk_01/processed/gait/edits").body["called"], "edits");
  EXPECT_EQ(api.last_name, "walk_01/gait");
  const std::string log = R"({"format": "mocap-edits", "version": 1, "operations": []})";
  EXPECT_EQ(Send(api, "PUT", "/api/sessions/walk_01/processed/gait/edits", log).body["called"], "putedits");
  EXPECT_EQ(api.last_request["format"], "mocap-edits");  // the service judges the log (processed_edits_test)
  FakeServiceApi other;
  EXPECT_EQ(Send(other, "PUT", "/api/sessions/walk_01/processed/gait/edits", "{").response.status, 400);
  EXPECT_EQ(Send(other, "POST", "/api/sessions/walk_01/processed/gait/edits", log).response.status, 405);
  EXPECT_EQ(Send(other, "GET", "/api/sessions/walk_01/processed/.x/edits").response.status, 404);
  EXPECT_TRUE(other.calls.empty());
}

TEST(ApiRouter, SessionPathsThatCouldLeaveTheSessionsDirectoryNeverReachTheService) {
  // The HTTP server hands the router decoded paths: "%2e%2e" arrives as "..", "%2f" as "/".
  const char* paths[] = {"/api/sessions/..", "/api/sessions/../files/x", "/api/sessions/a/files/..",
                         "/api/sessions/a/files/.hidden", "/api/sessions/.a/files/b",
                         "/api/sessions/a/files/../../etc/passwd", "/api/sessions/a/files/b/c",
                         "/api/sessions/a/files", "/api/sessions/a/other/b", "/api/sessions/a b",
                         "/api/sessions/a/files/b\\c", "/api/sessions/a\x01/files/b"};
  for (const char* path : paths) {
    FakeServiceApi api;
    const Routed r = Send(api, "GET", path);
    EXPECT_EQ(r.response.status, 404) << path;
    EXPECT_TRUE(r.body.contains("error")) << path;
    EXPECT_TRUE(r.response.file.empty()) << path;
    EXPECT_TRUE(api.calls.empty()) << path;
  }
  FakeServiceApi api;
  EXPECT_EQ(Send(api, "POST", "/api/sessions/a/files/b").response.status, 405);
  EXPECT_EQ(Send(api, "DELETE", "/api/sessions/a/files/b").response.status, 405);
  EXPECT_EQ(Send(api, "POST", "/api/blobs").response.status, 405);
  EXPECT_EQ(Send(api, "PUT", "/api/calibration").response.status, 405);
  EXPECT_TRUE(api.calls.empty());
}

TEST(ApiRouter, OversizedBodiesAndInvalidTextAreAnswered) {
  FakeServiceApi api;
  EXPECT_EQ(Send(api, "POST", "/api/capture/start", std::string(kMaxApiBody + 1, ' ')).response.status, 413);
  // Invalid UTF-8 in a field name comes back in the reason, replaced, never as an exception.
  const Routed r = Send(api, "POST", "/api/nodes/1/settings", "{\"\xff\xfe\": 1}");
  EXPECT_EQ(r.response.status, 400);
}

TEST(ApiRouter, WandingCarriesItsSettings) {
  FakeServiceApi api;
  const Routed started = Send(api, "POST", "/api/calibration/wand/start",
                              R"({"name": "wand1", "wand_length_mm": 500, "min_samples": 200, "coverage_target": 0.5,
                                  "timeout_s": 90, "grid_columns": 10, "refine_intrinsics": "focal-principal"})");
  ASSERT_EQ(started.response.status, 200) << started.response.body;
  EXPECT_EQ(api.last_wanding.session, "wand1");
  EXPECT_DOUBLE_EQ(api.last_wanding.wand_length_mm, 500.0);
  EXPECT_EQ(api.last_wanding.min_samples, 200u);
  EXPECT_DOUBLE_EQ(api.last_wanding.coverage_target, 0.5);
  EXPECT_DOUBLE_EQ(api.last_wanding.timeout_s, 90.0);
  EXPECT_EQ(api.last_wanding.coverage.columns, 10);
  EXPECT_EQ(api.last_wanding.coverage.rows, 6);  // the default stays
  EXPECT_EQ(api.last_wanding.refine_intrinsics, "focal-principal");
  EXPECT_FALSE(api.last_wanding.intrinsics.has_value());
  EXPECT_EQ(api.last_wanding.mode, "wand");  // the default
  ASSERT_EQ(Send(api, "POST", "/api/calibration/wand/start",
                 R"({"name": "m1", "mode": "single-marker", "wand_length_mm": 400, "min_scale_frames": 80})")
                .response.status,
            200);
  EXPECT_TRUE(api.last_wanding.SingleMarker());
  EXPECT_DOUBLE_EQ(api.last_wanding.wand_length_mm, 400.0);  // the scale bar's length
  EXPECT_EQ(api.last_wanding.min_scale_frames, 80u);
  EXPECT_EQ(Send(api, "GET", "/api/calibration/wand").body["called"], "wanding");
  EXPECT_EQ(Send(api, "POST", "/api/calibration/wand/stop").body["called"], "wandstop");
  EXPECT_TRUE(api.last_flag);  // stopping solves unless told not to
  Send(api, "POST", "/api/calibration/wand/stop", R"({"solve": false})");
  EXPECT_FALSE(api.last_flag);
  EXPECT_EQ(Send(api, "POST", "/api/calibration/wand/apply").body["called"], "wandapply");
  EXPECT_FALSE(api.last_flag);  // applying saves only when told
  Send(api, "POST", "/api/calibration/wand/apply", R"({"save": true})");
  EXPECT_TRUE(api.last_flag);
  EXPECT_EQ(Send(api, "POST", "/api/calibration/wand/solve").body["called"], "wandsolve");
  EXPECT_EQ(api.last_name, "");  // the refinement the wanding started with
  Send(api, "POST", "/api/calibration/wand/solve", R"({"refine_intrinsics": "all"})");
  EXPECT_EQ(api.last_name, "all");
}

TEST(ApiRouter, MonitorSolveIsAppliedPerCamera) {
  FakeServiceApi api;
  EXPECT_EQ(Send(api, "POST", "/api/calibration/monitor/apply", R"({"camera": 4})").body["called"], "monitorapply");
  EXPECT_EQ(api.last_number, 4u);
  EXPECT_FALSE(api.last_flag);  // saved only when told
  Send(api, "POST", "/api/calibration/monitor/apply", R"({"camera": 5, "save": true})");
  EXPECT_EQ(api.last_number, 5u);
  EXPECT_TRUE(api.last_flag);
  api.calls.clear();
  for (const char* body : {"{}", R"({"camera": -1})", R"({"camera": 4294967296})", R"({"camera": "4"})",
                           R"({"camera": 4, "save": 1})", R"({"camera": 4, "pose": []})"}) {
    EXPECT_EQ(Send(api, "POST", "/api/calibration/monitor/apply", body).response.status, 400) << body;
  }
  EXPECT_EQ(Send(api, "GET", "/api/calibration/monitor/apply").response.status, 405);
  EXPECT_EQ(Send(api, "POST", "/api/calibration/monitor/other", "{}").response.status, 404);
  EXPECT_TRUE(api.calls.empty());
}

TEST(ApiRouter, TheFloorStepTakesItsSettingsOrDefaults) {
  FakeServiceApi api;
  EXPECT_EQ(Send(api, "POST", "/api/calibration/world").body["called"], "world");
  EXPECT_EQ(api.last_world.method, "lframe");
  EXPECT_EQ(api.last_world.frames, 60);
  EXPECT_EQ(api.last_world.up_axis, 2);
  EXPECT_TRUE(api.last_world.lframe.empty());
  ASSERT_EQ(Send(api, "POST", "/api/calibration/world",
                 R"({"method": "lframe", "frames": 120, "up": "y", "max_fit_rms_mm": 3, "min_frames": 10,
                     "lframe": [[0, 0, 0], [300, 0, 0], [0, 0, 200]]})")
                .response.status,
            200);
  EXPECT_EQ(api.last_world.frames, 120);
  EXPECT_EQ(api.last_world.up_axis, 1);
  EXPECT_DOUBLE_EQ(api.last_world.max_fit_rms_mm, 3.0);
  EXPECT_EQ(api.last_world.min_frames, 10);
  ASSERT_EQ(api.last_world.lframe.size(), 3u);
  EXPECT_DOUBLE_EQ(api.last_world.lframe[1].x(), 300.0);
  Send(api, "POST", "/api/calibration/world", R"({"method": "floor"})");
  EXPECT_EQ(api.last_world.method, "floor");
  api.calls.clear();
  for (const char* body : {R"({"method": "wall"})", R"({"frames": 5})", R"({"frames": 3000})", R"({"up": "w"})",
                           R"({"up": 2})", R"({"lframe": [[0, 0, 0], [1, 0, 0]]})", R"({"lframe": [[0, 0], [1, 0, 0], [0, 1, 0]]})",
                           R"({"method": "floor", "lframe": [[0, 0, 0], [1, 0, 0], [0, 1, 0]]})",
                           R"({"frames": 20, "min_frames": 30})", R"({"max_fit_rms_mm": 0})", R"({"other": 1})"}) {
    EXPECT_EQ(Send(api, "POST", "/api/calibration/world", body).response.status, 400) << body;
  }
  EXPECT_EQ(Send(api, "GET", "/api/calibration/world").response.status, 405);
  EXPECT_TRUE(api.calls.empty());
}

TEST(ApiRouter, WandingIntrinsicsAreACalibrationDocument) {
  FakeServiceApi api;
  const std::string camera =
      R"({"id": 3, "width": 640, "height": 400, "fx": 500, "fy": 500, "cx": 320, "cy": 200,
          "distortion": [0, 0, 0, 0, 0], "rotation": [[1, 0, 0], [0, 1, 0], [0, 0, 1]], "translation": [0, 0, 0]})";
  ASSERT_EQ(Send(api, "POST", "/api/calibration/wand/start",
                 R"({"name": "w", "wand_length_mm": 300, "intrinsics": {"cameras": [)" + camera + "]}}")
                .response.status,
            200);
  ASSERT_TRUE(api.last_wanding.intrinsics.has_value());
  EXPECT_EQ(api.last_wanding.intrinsics->cameras.at(0).id, 3u);
  const Routed bad = Send(api, "POST", "/api/calibration/wand/start",
                          R"({"name": "w", "wand_length_mm": 300, "intrinsics": {"cameras": [{"id": 1}]}})");
  EXPECT_EQ(bad.response.status, 400);
  EXPECT_TRUE(bad.body.contains("error"));
}

TEST(ApiRouter, BadWandingRequestsAreRefusedBeforeTheService) {
  const char* bodies[] = {R"({"wand_length_mm": 500})",                        // no name
                          R"({"name": "w"})",                                  // no length
                          R"({"name": "../w", "wand_length_mm": 500})",        // a path, not a name
                          R"({"name": "w", "wand_length_mm": 5})",             // too short
                          R"({"name": "w", "wand_length_mm": "500"})",         // not a number
                          R"({"name": "w", "wand_length_mm": 500, "coverage_target": 1.5})",
                          R"({"name": "w", "wand_length_mm": 500, "min_samples": 2})",
                          R"({"name": "w", "wand_length_mm": 500, "timeout_s": 0})",
                          R"({"name": "w", "wand_length_mm": 500, "middle_marker_mm": 600})",
                          R"({"name": "w", "wand_length_mm": 500, "refine_intrinsics": "some"})",
                          R"({"name": "w", "wand_length_mm": 500, "grid_rows": 0})",
                          R"({"name": "w", "wand_length_mm": 500, "colour": "red"})",
                          R"({"name": "w", "wand_length_mm": 500, "mode": "light"})",
                          R"({"name": "w", "wand_length_mm": 500, "mode": 1})",
                          R"({"name": "w", "wand_length_mm": 500, "mode": "single-marker", "middle_marker_mm": 100})",
                          R"({"name": "w", "wand_length_mm": 500, "mode": "single-marker", "refine_intrinsics": "all"})",
                          R"({"name": "w", "wand_length_mm": 500, "min_scale_frames": 0})",
                          "[1]", "{"};
  for (const char* body : bodies) {
    FakeServiceApi api;
    const Routed r = Send(api, "POST", "/api/calibration/wand/start", body);
    EXPECT_EQ(r.response.status, 400) << body;
    EXPECT_TRUE(r.body.contains("error")) << body;
    EXPECT_TRUE(api.calls.empty()) << body;
  }
  FakeServiceApi api;
  EXPECT_EQ(Send(api, "GET", "/api/calibration/wand/start").response.status, 405);
  EXPECT_EQ(Send(api, "POST", "/api/calibration/wand").response.status, 405);
  EXPECT_EQ(Send(api, "POST", "/api/calibration/wand/solve", R"({"refine_intrinsics": "most"})").response.status, 400);
  EXPECT_EQ(Send(api, "POST", "/api/calibration/wand/solve", R"({"refine_intrinsics": 2})").response.status, 400);
  EXPECT_EQ(Send(api, "POST", "/api/calibration/wand/refine").response.status, 404);
  EXPECT_EQ(Send(api, "GET", "/api/calibration/wand/stop/now").response.status, 404);
  EXPECT_EQ(Send(api, "POST", "/api/calibration/wand/stop", R"({"solve": 1})").response.status, 400);
  EXPECT_EQ(Send(api, "POST", "/api/calibration/wand/apply", R"({"keep": true})").response.status, 400);
  EXPECT_TRUE(api.calls.empty());
}

}  // namespace
}  // namespace mocap::service
