// `calibrate wand`'s report printing and live mode (see wand_client.h). Ctrl-C (or SIGTERM)
// while collecting cancels the wanding in serve.
#include "cli/wand_client.h"

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <thread>

#include "cli/api_client.h"
#include "util/json_file.h"

namespace mocap {
namespace {

using nlohmann::json;

std::atomic<bool> g_interrupted{false};
void OnInterrupt(int) { g_interrupted.store(true); }

double Num(const json& j, const char* key) { return j.contains(key) && j[key].is_number() ? j[key].get<double>() : 0.0; }

std::string Text(const json& j, const char* key) {
  return j.contains(key) && j[key].is_string() ? j[key].get<std::string>() : "";
}

// One progress line per camera: samples, coverage and what to do.
void PrintProgress(const json& collection) {
  std::printf("%.0f s of %.0f s, %zu frame sets, %zu with the wand\n", Num(collection, "elapsed_s"),
              Num(collection, "timeout_s"), static_cast<size_t>(Num(collection, "frame_sets")),
              static_cast<size_t>(Num(collection, "wand_frames")));
  for (const json& c : collection["cameras"]) std::printf("  %s\n", Text(c, "advice").c_str());
  std::fflush(stdout);
}

void SaveSessionFile(const std::string& api, const std::string& session, const std::string& file,
                     const std::string& path) {
  const ApiAnswer answer = CallApi(api, "GET", "/api/sessions/" + session + "/files/" + file);
  if (answer.status != 200)
    throw std::runtime_error(session + "/" + file + ": serve answered HTTP " + std::to_string(answer.status));
  WriteTextFile(answer.body, path);
}

}  // namespace

std::string RatingRule(const json& t) {
  static const char* const kNames[] = {"Exceptional", "Excellent", "Good", "Fair"};
  auto part = [&](const json& limits, const char* unit) {
    std::string s;
    for (const char* n : kNames) {
      char buffer[64];
      std::snprintf(buffer, sizeof(buffer), "%s%s <= %g %s", s.empty() ? "" : ", ", n, limits.value(n, 0.0), unit);
      s += buffer;
    }
    return s;
  };
  return "ratings (the worse figure decides, above Fair is Poor, a refused camera is Poor): reprojection RMS " +
         part(t["reprojection_rms_px"], "px") + "; wand length RMS " + part(t["wand_length_rms_mm"], "mm");
}

void PrintWandReport(const json& report) {
  std::printf("calibrate wand: %zu/%zu cameras accepted, reference camera %u, %zu of %zu frames used "
              "(%zu selected), %d solver iterations, %.1f s; rig rated %s\n",
              report["cameras_accepted"].get<size_t>(), report["cameras"].size(),
              report["reference_camera"].get<unsigned>(), report["frames_used"].get<size_t>(),
              report["frames"].get<size_t>(), report["frames_selected"].get<size_t>(),
              report["solver_iterations"].get<int>(), report["seconds"].get<double>(),
              report["rating"].get<std::string>().c_str());
  std::printf("%6s %7s %7s %8s %9s %12s %12s  %-12s %s\n", "camera", "views", "used", "rms_px", "coverage",
              "len_rms_mm", "len_p95_mm", "rating", "status");
  for (const auto& c : report["cameras"]) {
    const std::string status = c["accepted"].get<bool>() ? "ok" : "REFUSED: " + c["reason"].get<std::string>();
    std::printf("%6u %7zu %7zu %8.3f %8.0f%% %12.3f %12.3f  %-12s %s\n", c["id"].get<unsigned>(),
                c["views_selected"].get<size_t>(), c["views_used"].get<size_t>(),
                c["reprojection_rms_px"].get<double>(), 100.0 * c["coverage"].get<double>(),
                c["wand_length_error"]["rms_mm"].get<double>(), c["wand_length_error"]["p95_abs_mm"].get<double>(),
                c["rating"].get<std::string>().c_str(), status.c_str());
  }
  const json& w = report["wand_length_error"];
  std::printf("reprojection RMS %.3f px (2-D error length per observation); wand length error over %zu frames: "
              "mean %+.3f mm, rms %.3f mm, median |e| %.3f mm, p95 %.3f mm, max %.3f mm\n",
              report["reprojection_rms_px"].get<double>(), w["frames"].get<size_t>(), w["mean_mm"].get<double>(),
              w["rms_mm"].get<double>(), w["median_abs_mm"].get<double>(), w["p95_abs_mm"].get<double>(),
              w["max_abs_mm"].get<double>());
  std::printf("%s\n", RatingRule(report["rating_thresholds"]).c_str());
}

void RunLiveWanding(const LiveWandingArgs& args) {
  json start = args.start;
  start["name"] = args.session;
  json state = CallApiJson(args.api, "POST", "/api/calibration/wand/start", start);
  // Ctrl-C while collecting cancels the wanding in serve too, rather than leaving it running.
  g_interrupted.store(false);
  std::signal(SIGINT, OnInterrupt);
  std::signal(SIGTERM, OnInterrupt);
  if (!args.json)
    std::printf("wanding %s: wave the wand through the volume; serve stops when every camera has enough\n",
                args.session.c_str());
  const auto poll = std::chrono::duration<double>(args.poll_s);
  auto last_print = std::chrono::steady_clock::now() - std::chrono::hours(1);
  // Collecting ends by serve's own timeout (at most an hour); the solve is waited for as long as
  // solve_wait_s, so the loop is bounded either way.
  const double timeout_s = state["collection"].value("timeout_s", 3600.0);
  const auto collect_deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s + 30.0);
  while (Text(state, "state") == "collecting") {
    if (g_interrupted.load()) {
      CallApiJson(args.api, "POST", "/api/calibration/wand/stop", json{{"solve", false}});
      throw std::runtime_error("interrupted: wanding " + args.session + " cancelled (its recording stays in serve's "
                               "sessions directory)");
    }
    if (std::chrono::steady_clock::now() > collect_deadline)
      throw std::runtime_error("serve kept collecting past its timeout; stop it with POST /api/calibration/wand/stop");
    const auto now = std::chrono::steady_clock::now();
    if (args.json) {
      std::printf("%s\n", json{{"state", "collecting"}, {"collection", state["collection"]}}.dump().c_str());
      std::fflush(stdout);
    } else if (now - last_print >= std::chrono::seconds(2)) {
      PrintProgress(state["collection"]);
      last_print = now;
    }
    std::this_thread::sleep_for(poll);
    state = CallApiJson(args.api, "GET", "/api/calibration/wand");
  }
  if (!args.json) {
    std::printf("wanding %s stopped: %s\n", args.session.c_str(), Text(state, "stop_reason").c_str());
    if (state["collection"].is_object()) PrintProgress(state["collection"]);
    std::printf("solving...\n");
    std::fflush(stdout);
  }
  const auto solve_deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(args.solve_wait_s);
  while (Text(state, "state") == "solving") {
    if (std::chrono::steady_clock::now() > solve_deadline)
      throw std::runtime_error("serve's solve took longer than " + std::to_string(args.solve_wait_s) + " s");
    std::this_thread::sleep_for(poll);
    state = CallApiJson(args.api, "GET", "/api/calibration/wand");
  }
  const std::string final_state = Text(state, "state");
  if (final_state == "failed")
    throw std::runtime_error("no calibration from wanding " + args.session + ": " + Text(state["solve"], "error"));
  if (final_state != "solved")
    throw std::runtime_error("wanding " + args.session + " ended " + final_state + " (" + Text(state, "stop_reason") +
                             ")");
  const json& report = state["solve"]["report"];
  if (args.json) {
    std::printf("%s\n", json{{"state", "solved"}, {"stop_reason", state["stop_reason"]}, {"report", report}}
                            .dump()
                            .c_str());
  } else {
    PrintWandReport(report);
  }
  if (!args.report_dir.empty()) {
    const std::filesystem::path dir(args.report_dir);
    SaveSessionFile(args.api, args.session, "wand_report.html", (dir / "wand_report.html").string());
    SaveSessionFile(args.api, args.session, "wand_figures.json", (dir / "wand_figures.json").string());
    if (!args.json) std::printf("report: %s\n", (dir / "wand_report.html").string().c_str());
  }
  const bool all_accepted = state["solve"].value("all_accepted", false);
  if (!all_accepted && !args.allow_partial) {
    std::string reasons;
    for (const json& c : report["cameras"])
      if (!c.value("accepted", false))
        reasons += (reasons.empty() ? "" : "; ") + std::string("camera ") + std::to_string(c.value("id", 0)) + ": " +
                   Text(c, "reason");
    throw std::runtime_error("calibration refused, nothing applied or written (--allow-partial writes the accepted "
                             "cameras): " + reasons);
  }
  if (!args.output.empty()) SaveSessionFile(args.api, args.session, "wand_calibration.json", args.output);
  if (args.apply) {
    const json applied = CallApiJson(args.api, "POST", "/api/calibration/wand/apply", json{{"save", args.save}});
    if (!args.json)
      std::printf("applied to serve's live reconstruction%s\n",
                  applied["saved_to"].is_string() ? (" and saved to " + applied["saved_to"].get<std::string>()).c_str()
                                                  : "");
  }
  if (!args.json)
    std::printf("the recorded wand session stays in serve's sessions directory as %s: `calibrate wand` solves it "
                "again offline\n", args.session.c_str());
}

}  // namespace mocap
