// Routing and validation of API requests (see api_router.h).
#include "service/api_router.h"

#include <cstdint>
#include <map>
#include <optional>
#include <vector>

#include "calib/wand_bundle_adjustment.h"
#include "io/calibration_json.h"
#include "service/api_error.h"
#include "service/session_name.h"

namespace mocap::service {
namespace {

using nlohmann::json;

std::vector<std::string> Segments(const std::string& path) {
  std::vector<std::string> parts;
  size_t start = 1;
  while (start <= path.size()) {
    const size_t end = path.find('/', start);
    const std::string part = path.substr(start, end == std::string::npos ? std::string::npos : end - start);
    if (!part.empty()) parts.push_back(part);
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return parts;
}

uint32_t ParseNodeId(const std::string& text) {
  if (text.empty() || text.size() > 10) throw ApiError(404, "no node '" + text + "'");
  uint64_t value = 0;
  for (char c : text) {
    if (c < '0' || c > '9') throw ApiError(404, "no node '" + text + "' (node ids are numbers)");
    value = value * 10 + static_cast<uint64_t>(c - '0');
  }
  if (value == 0 || value > UINT32_MAX) throw ApiError(404, "no node " + text);
  return static_cast<uint32_t>(value);
}

std::map<std::string, std::string> ParseQuery(const std::string& query) {
  std::map<std::string, std::string> out;
  size_t start = 0;
  while (start < query.size()) {
    size_t end = query.find('&', start);
    if (end == std::string::npos) end = query.size();
    const std::string pair = query.substr(start, end - start);
    const size_t eq = pair.find('=');
    if (!pair.empty()) out[pair.substr(0, eq)] = eq == std::string::npos ? "" : pair.substr(eq + 1);
    start = end + 1;
  }
  return out;
}

// The body as a JSON object whose fields are all among `allowed` (empty body: {}).
json ParseBody(const std::string& body, const std::vector<std::string>& allowed) {
  if (body.empty()) return json::object();
  json j = json::parse(body, nullptr, false);
  if (j.is_discarded()) throw ApiError(400, "the body is not valid JSON");
  if (!j.is_object()) throw ApiError(400, "the body must be a JSON object");
  for (const auto& [key, value] : j.items()) {
    bool known = false;
    for (const std::string& a : allowed) known = known || a == key;
    if (!known) throw ApiError(400, "unknown field '" + key + "'");
  }
  return j;
}

std::optional<int64_t> IntegerField(const json& body, const std::string& name, int64_t lo, int64_t hi) {
  if (!body.contains(name)) return std::nullopt;
  const json& v = body[name];
  if (!v.is_number_integer()) throw ApiError(400, "'" + name + "' must be an integer");
  const int64_t value = v.is_number_unsigned() && v.get<uint64_t>() > static_cast<uint64_t>(INT64_MAX)
                            ? INT64_MAX
                            : v.get<int64_t>();
  if (value < lo || value > hi)
    throw ApiError(400, "'" + name + "' must be " + std::to_string(lo) + ".." + std::to_string(hi));
  return value;
}

void RequireMethod(const ApiRequest& r, const char* method) {
  if (r.method != method) throw ApiError(405, r.method + " " + r.path + ": use " + method);
}

// Text from outside (names, keys) may hold invalid UTF-8: replaced, never a throw.
std::string Dump(const json& j) { return j.dump(-1, ' ', false, json::error_handler_t::replace); }

ApiResponse Json(const json& j) {
  ApiResponse response;
  response.body = Dump(j);
  return response;
}

ApiResponse RouteNode(ServiceApi& api, const ApiRequest& r, const std::vector<std::string>& s) {
  const uint32_t id = ParseNodeId(s[2]);
  if (s.size() == 3) {
    RequireMethod(r, "GET");
    return Json(api.Node(id));
  }
  if (s.size() != 4) throw ApiError(404, "no such path: " + r.path);
  if (s[3] == "settings") {
    RequireMethod(r, "POST");
    const json body = ParseBody(r.body, {"threshold", "auto_threshold", "exposure_us", "gain_milli",
                                         "brightness_pct", "contrast_pct"});
    CameraSettings settings;
    if (auto v = IntegerField(body, "threshold", 1, 255)) settings.threshold = static_cast<uint32_t>(*v);
    if (auto v = IntegerField(body, "exposure_us", 1, 1'000'000)) settings.exposure_us = static_cast<uint32_t>(*v);
    if (auto v = IntegerField(body, "gain_milli", 1000, 64000)) settings.gain_milli = static_cast<uint32_t>(*v);
    if (auto v = IntegerField(body, "brightness_pct", 0, 100)) settings.brightness_pct = static_cast<uint32_t>(*v);
    if (auto v = IntegerField(body, "contrast_pct", 0, 100)) settings.contrast_pct = static_cast<uint32_t>(*v);
    if (body.contains("auto_threshold")) {
      if (!body["auto_threshold"].is_boolean()) throw ApiError(400, "'auto_threshold' must be true or false");
      settings.auto_threshold = body["auto_threshold"].get<bool>();
    }
    if (settings.threshold && settings.auto_threshold)
      throw ApiError(400, "give 'threshold' or 'auto_threshold', not both");
    if (!settings.threshold && !settings.auto_threshold && !settings.exposure_us && !settings.gain_milli &&
        !settings.brightness_pct && !settings.contrast_pct)
      throw ApiError(400,
                     "nothing to set: give threshold, auto_threshold, exposure_us, gain_milli, brightness_pct or "
                     "contrast_pct");
    return Json(api.Configure(id, settings));
  }
  if (s[3] == "identify") {
    RequireMethod(r, "POST");
    const json body = ParseBody(r.body, {"duration_ms"});
    const int64_t duration = IntegerField(body, "duration_ms", 100, 60000).value_or(3000);
    return Json(api.Identify(id, static_cast<uint32_t>(duration)));
  }
  if (s[3] == "preview") {
    RequireMethod(r, "GET");
    const auto query = ParseQuery(r.query);
    bool thresholded = false;
    uint32_t downscale = 2;
    for (const auto& [key, value] : query) {
      if (key == "mode") {
        if (value != "raw" && value != "thresholded") throw ApiError(400, "mode must be raw or thresholded");
        thresholded = value == "thresholded";
      } else if (key == "downscale") {
        if (value != "1" && value != "2" && value != "4" && value != "8")
          throw ApiError(400, "downscale must be 1, 2, 4 or 8");
        downscale = static_cast<uint32_t>(value[0] - '0');
      } else {
        throw ApiError(400, "unknown query parameter '" + key + "'");
      }
    }
    ApiResponse response;
    const std::vector<uint8_t> png = api.PreviewPng(id, thresholded, downscale);
    response.content_type = "image/png";
    response.body.assign(png.begin(), png.end());
    return response;
  }
  throw ApiError(404, "no such path: " + r.path);
}

// What a downloaded session file is, by its extension; anything unknown is bytes.
std::string FileType(const std::string& file) {
  const size_t dot = file.rfind('.');
  const std::string ext = dot == std::string::npos ? "" : file.substr(dot + 1);
  if (ext == "trc" || ext == "txt") return "text/plain; charset=utf-8";
  if (ext == "tsv") return "text/tab-separated-values; charset=utf-8";
  if (ext == "json") return "application/json";
  if (ext == "csv") return "text/csv; charset=utf-8";
  if (ext == "html") return "text/html; charset=utf-8";  // the wand calibration report
  return "application/octet-stream";
}

// /api/sessions/NAME[/files/FILE | /process | /processed/RECIPE/files/FILE | /processed/RECIPE/edits]:
// names are checked
// here as the service names sessions, so a path that could leave the sessions directory ("..",
// "/", a leading dot) never reaches it.
ApiResponse RouteSession(ServiceApi& api, const ApiRequest& r, const std::vector<std::string>& s) {
  const std::string& name = s[2];
  if (!ValidSessionName(name)) throw ApiError(404, "no session '" + name + "'");
  if (s.size() == 3 && r.method == "DELETE") return Json(api.DeleteSession(name));
  if (s.size() == 4 && s[3] == "rename") {
    RequireMethod(r, "POST");
    const json body = ParseBody(r.body, {"name"});
    if (!body.contains("name") || !body["name"].is_string()) throw ApiError(400, "'name' (a string) is required");
    return Json(api.RenameSession(name, body["name"].get<std::string>()));
  }
  if (s.size() == 4 && s[3] == "notes") {
    RequireMethod(r, "PUT");
    const json body = ParseBody(r.body, {"notes"});
    if (!body.contains("notes") || !body["notes"].is_string()) throw ApiError(400, "'notes' (a string) is required");
    return Json(api.AnnotateSession(name, body["notes"].get<std::string>()));
  }
  if (s.size() == 4 && s[3] == "process") {
    RequireMethod(r, "POST");
    const json body = ParseBody(r.body, {"recipe", "overwrite"});
    ApiResponse response = Json(api.ProcessSession(name, body));
    response.status = 202;
    return response;
  }
  if (s.size() == 6 && s[3] == "processed" && s[5] == "edits") {
    const std::string& recipe = s[4];
    if (!ValidSessionName(recipe)) throw ApiError(404, "session '" + name + "' has no results of recipe '" + recipe + "'");
    if (r.method == "PUT") {
      const json log = json::parse(r.body, nullptr, false);
      if (log.is_discarded()) throw ApiError(400, "the body is not valid JSON");
      return Json(api.PutProcessedEdits(name, recipe, log));
    }
    RequireMethod(r, "GET");
    return Json(api.ProcessedEdits(name, recipe));
  }
  RequireMethod(r, "GET");
  if (s.size() == 3) return Json(api.Session(name));
  ApiResponse response;
  if (s.size() == 5 && s[3] == "files") {
    const std::string& file = s[4];
    if (!ValidSessionName(file)) throw ApiError(404, "session '" + name + "' has no file '" + file + "'");
    response.file = api.SessionFile(name, file);
  } else if (s.size() == 7 && s[3] == "processed" && s[5] == "files") {
    const std::string &recipe = s[4], &file = s[6];
    if (!ValidSessionName(recipe) || !ValidSessionName(file))
      throw ApiError(404, "session '" + name + "' has no file '" + file + "' of recipe '" + recipe + "'");
    response.file = api.ProcessedFile(name, recipe, file);
  } else {
    throw ApiError(404, "no such path: " + r.path);
  }
  response.content_type = FileType(s.back());
  return response;
}

std::optional<double> NumberField(const json& body, const std::string& name, double lo, double hi) {
  if (!body.contains(name)) return std::nullopt;
  const json& v = body[name];
  if (!v.is_number()) throw ApiError(400, "'" + name + "' must be a number");
  const double value = v.get<double>();
  if (!(value >= lo && value <= hi))
    throw ApiError(400, "'" + name + "' must be within " + json(lo).dump() + ".." + json(hi).dump());
  return value;
}

// POST /api/calibration/wand/start: the wanding's settings; ranges are checked again (and
// completely) by WandingOptions::Check in the service.
WandingOptions WandingFromBody(const std::string& text) {
  const json body = ParseBody(text, {"name", "mode", "wand_length_mm", "middle_marker_mm", "min_samples",
                                     "min_scale_frames", "coverage_target", "timeout_s", "refine_intrinsics",
                                     "intrinsics", "grid_columns", "grid_rows", "cell_samples"});
  WandingOptions o;
  if (!body.contains("name") || !body["name"].is_string()) throw ApiError(400, "'name' (a string) is required");
  o.session = body["name"].get<std::string>();
  if (body.contains("mode")) {
    if (!body["mode"].is_string()) throw ApiError(400, "'mode' must be wand or single-marker");
    o.mode = body["mode"].get<std::string>();
  }
  if (!body.contains("wand_length_mm")) throw ApiError(400, "'wand_length_mm' is required");
  o.wand_length_mm = *NumberField(body, "wand_length_mm", 10.0, 5000.0);
  o.middle_marker_mm = NumberField(body, "middle_marker_mm", 0.0, 5000.0).value_or(0.0);
  o.min_samples = static_cast<size_t>(IntegerField(body, "min_samples", 10, 1'000'000).value_or(300));
  o.min_scale_frames =
      static_cast<size_t>(IntegerField(body, "min_scale_frames", 1, 1'000'000).value_or(o.min_scale_frames));
  o.coverage_target = NumberField(body, "coverage_target", 0.05, 1.0).value_or(o.coverage_target);
  o.timeout_s = NumberField(body, "timeout_s", 1.0, 3600.0).value_or(o.timeout_s);
  o.coverage.columns = static_cast<int>(IntegerField(body, "grid_columns", 1, 64).value_or(o.coverage.columns));
  o.coverage.rows = static_cast<int>(IntegerField(body, "grid_rows", 1, 64).value_or(o.coverage.rows));
  o.coverage.cell_samples = static_cast<int>(IntegerField(body, "cell_samples", 1, 100000).value_or(o.coverage.cell_samples));
  if (body.contains("refine_intrinsics")) {
    if (!body["refine_intrinsics"].is_string())
      throw ApiError(400, "'refine_intrinsics' must be none, focal-principal or all");
    o.refine_intrinsics = body["refine_intrinsics"].get<std::string>();
  }
  if (body.contains("intrinsics")) {
    try {
      o.intrinsics = RigFromJson(body["intrinsics"], "'intrinsics'");
    } catch (const std::exception& e) {
      throw ApiError(400, e.what());
    }
  }
  o.Check();
  return o;
}

// POST /api/calibration/world: {"method": "lframe" | "floor", "frames", "up": "x" | "y" | "z",
// "lframe": [[x, y, z], ...] mm, "max_fit_rms_mm", "min_frames"}, every field optional.
WorldFrameRequest WorldFrameFromBody(const std::string& text) {
  const json body = ParseBody(text, {"method", "frames", "up", "lframe", "max_fit_rms_mm", "min_frames"});
  WorldFrameRequest o;
  if (body.contains("method")) {
    if (!body["method"].is_string()) throw ApiError(400, "'method' must be lframe or floor");
    o.method = body["method"].get<std::string>();
  }
  o.frames = static_cast<int>(IntegerField(body, "frames", 10, 2000).value_or(o.frames));
  o.min_frames = static_cast<int>(IntegerField(body, "min_frames", 1, 2000).value_or(o.min_frames));
  o.max_fit_rms_mm = NumberField(body, "max_fit_rms_mm", 0.01, 100.0).value_or(o.max_fit_rms_mm);
  if (body.contains("up")) {
    const json& up = body["up"];
    if (!up.is_string() || (up != "x" && up != "y" && up != "z")) throw ApiError(400, "'up' must be x, y or z");
    o.up_axis = up == "x" ? 0 : up == "y" ? 1 : 2;
  }
  if (body.contains("lframe")) {
    const json& markers = body["lframe"];
    if (!markers.is_array() || markers.size() < 3 || markers.size() > 8)
      throw ApiError(400, "'lframe' must list 3..8 markers as [x, y, z] in mm");
    for (const json& m : markers) {
      if (!m.is_array() || m.size() != 3 || !m[0].is_number() || !m[1].is_number() || !m[2].is_number())
        throw ApiError(400, "'lframe' must list 3..8 markers as [x, y, z] in mm");
      o.lframe.emplace_back(m[0].get<double>(), m[1].get<double>(), m[2].get<double>());
    }
  }
  o.Check();
  return o;
}

// /api/calibration/wand[/start|/stop|/solve|/apply]
ApiResponse RouteWanding(ServiceApi& api, const ApiRequest& r, const std::vector<std::string>& s) {
  if (s.size() == 3) {
    RequireMethod(r, "GET");
    return Json(api.Wanding());
  }
  if (s.size() != 4) throw ApiError(404, "no such path: " + r.path);
  RequireMethod(r, "POST");
  if (s[3] == "start") return Json(api.StartWanding(WandingFromBody(r.body)));
  if (s[3] == "solve") {
    const json body = ParseBody(r.body, {"refine_intrinsics"});
    std::string refine;
    if (body.contains("refine_intrinsics")) {
      if (!body["refine_intrinsics"].is_string())
        throw ApiError(400, "'refine_intrinsics' must be none, focal-principal or all");
      refine = body["refine_intrinsics"].get<std::string>();
      try {
        IntrinsicsRefinementFromName(refine);
      } catch (const std::invalid_argument& e) {
        throw ApiError(400, e.what());
      }
    }
    return Json(api.SolveWanding(refine));
  }
  if (s[3] == "stop" || s[3] == "apply") {
    const char* flag = s[3] == "stop" ? "solve" : "save";
    const json body = ParseBody(r.body, {flag});
    bool value = s[3] == "stop";  // stop solves unless told not to; apply saves only when told
    if (body.contains(flag)) {
      if (!body[flag].is_boolean()) throw ApiError(400, std::string("'") + flag + "' must be true or false");
      value = body[flag].get<bool>();
    }
    return Json(s[3] == "stop" ? api.StopWanding(value) : api.ApplyWandCalibration(value));
  }
  throw ApiError(404, "no such path: " + r.path);
}

ApiResponse Route(ServiceApi& api, const ApiRequest& r) {
  if (r.body.size() > kMaxApiBody) throw ApiError(413, "the body is larger than 64 KiB");
  const std::vector<std::string> s = Segments(r.path);
  if (s.size() < 2 || s[0] != "api") throw ApiError(404, "no such path: " + r.path);
  const std::string& what = s[1];
  if (what == "status" && s.size() == 2) {
    RequireMethod(r, "GET");
    return Json(api.Status());
  }
  if (what == "nodes" && s.size() == 2) {
    RequireMethod(r, "GET");
    return Json(api.Nodes());
  }
  if (what == "nodes") return RouteNode(api, r, s);
  if (what == "masks" && s.size() == 2) {
    RequireMethod(r, "DELETE");
    return Json(api.ClearMasks());
  }
  if (what == "masks" && s.size() == 3 && s[2] == "auto") {
    RequireMethod(r, "POST");
    const json body = ParseBody(r.body, {"frames"});
    return Json(api.AutoMask(static_cast<int>(IntegerField(body, "frames", 10, 100000).value_or(100))));
  }
  if (what == "capture" && s.size() == 3 && s[2] == "start") {
    RequireMethod(r, "POST");
    const json body = ParseBody(r.body, {"name"});
    if (!body.contains("name") || !body["name"].is_string()) throw ApiError(400, "'name' (a string) is required");
    return Json(api.StartCapture(body["name"].get<std::string>()));
  }
  if (what == "capture" && s.size() == 3 && s[2] == "stop") {
    RequireMethod(r, "POST");
    ParseBody(r.body, {});
    return Json(api.StopCapture());
  }
  if (what == "sessions" && s.size() == 2) {
    RequireMethod(r, "GET");
    return Json(api.Sessions());
  }
  if (what == "sessions") return RouteSession(api, r, s);
  if (what == "processing" && s.size() == 2) {
    RequireMethod(r, "GET");
    return Json(api.Processing());
  }
  if (what == "calibration" && s.size() == 2) {
    RequireMethod(r, "GET");
    return Json(api.Calibration());
  }
  if (what == "calibration" && s.size() >= 3 && s[2] == "wand") return RouteWanding(api, r, s);
  if (what == "calibration" && s.size() == 3 && s[2] == "world") {
    RequireMethod(r, "POST");
    return Json(api.SetWorldFrame(WorldFrameFromBody(r.body)));
  }
  if (what == "calibration" && s.size() == 4 && s[2] == "monitor" && s[3] == "apply") {
    RequireMethod(r, "POST");
    const json body = ParseBody(r.body, {"camera", "save"});
    if (!body.contains("camera") || !body["camera"].is_number_unsigned() || body["camera"].get<uint64_t>() > 0xffffffffu)
      throw ApiError(400, "'camera' (the id of the camera whose solved pose to apply) must be an id 0..4294967295");
    bool save = false;
    if (body.contains("save")) {
      if (!body["save"].is_boolean()) throw ApiError(400, "'save' must be true or false");
      save = body["save"].get<bool>();
    }
    return Json(api.ApplyMonitorSolve(body["camera"].get<uint32_t>(), save));
  }
  if (what == "blobs" && s.size() == 2) {
    RequireMethod(r, "GET");
    return Json(api.Blobs());
  }
  throw ApiError(404, "no such path: " + r.path);
}

ApiResponse Error(int status, const std::string& message) {
  ApiResponse response;
  response.status = status;
  response.body = Dump(json{{"error", message}});
  return response;
}

}  // namespace

ApiResponse HandleApiRequest(ServiceApi& api, const ApiRequest& request) {
  try {
    return Route(api, request);
  } catch (const ApiError& e) {
    return Error(e.status, e.what());
  } catch (const std::exception& e) {
    return Error(500, e.what());
  }
}

}  // namespace mocap::service
