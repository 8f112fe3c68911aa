// The operator's commands for a running `serve` (each one HTTP request to its API):
//   status, nodes, node ID set|preview|identify, mask auto|clear, capture start|stop, sessions.
// Results go to stdout as a table (or JSON with --json); a refused request exits 1 with the
// service's reason.
#include <cstdio>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli/api_client.h"
#include "cli/commands.h"
#include "cli/node_table.h"

namespace mocap {
namespace {

using nlohmann::json;

void Print(const json& j) { std::printf("%s\n", j.dump(2).c_str()); }

std::string Str(const json& j, const char* key) { return JsonFieldText(j, key); }

void PrintNodes(const json& nodes) {
  std::printf("%s\n", NodeTableHeader().c_str());
  for (const json& n : nodes) std::printf("%s\n", NodeTableRow(n).c_str());
}

void PrintStatus(const json& s) {
  const json& l = s["hub_latency_ms"];
  std::printf("up %.0f s; nodes %s online of %s known (%s cameras calibrated); UDP port %s\n",
              s["uptime_s"].get<double>(), Str(s, "nodes_online").c_str(), Str(s, "nodes_known").c_str(),
              Str(s, "cameras").c_str(), Str(s, "udp_port").c_str());
  std::printf("frame sets %s (%s incomplete, %s of one camera only); points %s (%s provisional); markers confirmed %s\n",
              Str(s, "frame_sets").c_str(), Str(s, "incomplete_frame_sets").c_str(),
              Str(s, "single_camera_frame_sets").c_str(), Str(s, "points_published").c_str(),
              Str(s, "provisional_points_published").c_str(), Str(s, "markers_confirmed").c_str());
  std::printf("hub latency (last datagram -> 3D published): p50 %.3f ms, p99 %.3f ms, max %.3f ms\n",
              l["p50"].get<double>(), l["p99"].get<double>(), l["max"].get<double>());
  std::printf("bad input: %s malformed, %s from unknown nodes, %s unauthentic; masks for %s cameras\n",
              Str(s, "malformed_datagrams").c_str(), Str(s, "unknown_datagrams").c_str(),
              Str(s, "unauthentic_datagrams").c_str(), Str(s, "masks").c_str());
  if (s.contains("wire")) {
    const json& w = s["wire"];
    if (w.value("mode", "") == "insecure-dev")
      std::printf("WIRE: INSECURE (--insecure-dev-wire): nothing is authenticated; development only\n");
    else
      std::printf("wire: authenticated, keys of %s nodes; %s datagrams refused %s\n", Str(w, "nodes_with_keys").c_str(),
                  Str(w, "rejected").c_str(), w["rejected_by_kind"].dump().c_str());
  }
  if (s["capture"].is_null()) {
    std::printf("capture: none running\n");
  } else {
    std::printf("capture: %s running for %.1f s, %s frame sets -> %s\n", Str(s["capture"], "name").c_str(),
                s["capture"]["seconds"].get<double>(), Str(s["capture"], "frame_sets").c_str(),
                Str(s["capture"], "path").c_str());
  }
  const json& last = s.value("last_capture", json());
  if (last.is_object() && last.value("state", "") == "failed")
    std::printf("CAPTURE FAILED: %s: %s (%s frame sets kept)\n", Str(last, "name").c_str(), Str(last, "reason").c_str(),
                Str(last, "frame_sets").c_str());
  const json& disk = s.value("sessions_disk", json());
  if (disk.is_object() && disk.value("low", false))
    std::printf("SESSIONS DISK LOW: %.0f MiB free (warned below %s MiB)\n",
                disk.value("free_bytes", 0.0) / (1024.0 * 1024.0), Str(disk, "warn_free_mb").c_str());
}

// "threshold=40", "exposure-us=2000", "gain-milli=2500", "brightness=60", "auto-threshold" -> the settings
// request body.
json SettingsBody(const std::vector<std::string>& assignments) {
  json body = json::object();
  for (const std::string& a : assignments) {
    const size_t eq = a.find('=');
    const std::string key = a.substr(0, eq);
    const std::string value = eq == std::string::npos ? "" : a.substr(eq + 1);
    auto integer = [&](const char* what) {
      size_t used = 0;
      long long v = -1;
      try {
        v = std::stoll(value, &used);
      } catch (const std::exception&) {
      }
      if (value.empty() || used != value.size() || v < 0) throw UsageError(std::string(what) + " needs a number: " + a);
      return v;
    };
    if (key == "threshold" && value == "auto") body["auto_threshold"] = true;
    else if (key == "threshold") body["threshold"] = integer("threshold");
    else if (key == "auto-threshold" && value.empty()) body["auto_threshold"] = true;
    else if (key == "exposure-us") body["exposure_us"] = integer("exposure-us");
    else if (key == "gain-milli") body["gain_milli"] = integer("gain-milli");
    else if (key == "brightness") body["brightness_pct"] = integer("brightness");
    else if (key == "contrast") body["contrast_pct"] = integer("contrast");
    else
      throw UsageError("unknown setting '" + a +
                       "' (threshold=N|auto, exposure-us=N, gain-milli=N, brightness=PCT, contrast=PCT)");
  }
  if (body.empty()) throw UsageError("give at least one setting, e.g. threshold=40");
  return body;
}

// `status`: the service's figures.
void AddStatusCommand(CLI::App& app) {
  auto api = std::make_shared<std::string>();
  auto as_json = std::make_shared<bool>(false);
  CLI::App* c = app.add_subcommand("status", "Ask a running serve how it is doing");
  AddApiOption(*c, api.get());
  c->add_flag("--json", *as_json, "Print the JSON answer");
  c->callback([api, as_json] {
    const json s = CallApiJson(*api, "GET", "/api/status");
    *as_json ? Print(s) : PrintStatus(s);
  });
}

// `nodes`: the node table.
void AddNodesCommand(CLI::App& app) {
  auto api = std::make_shared<std::string>();
  auto as_json = std::make_shared<bool>(false);
  CLI::App* c = app.add_subcommand("nodes", "The node table of a running serve");
  AddApiOption(*c, api.get());
  c->add_flag("--json", *as_json, "Print the JSON answer");
  c->callback([api, as_json] {
    const json nodes = CallApiJson(*api, "GET", "/api/nodes");
    *as_json ? Print(nodes) : PrintNodes(nodes);
  });
}

// `node ID set|preview|identify`: one node steered through serve.
void AddNodeCommand(CLI::App& app) {
  CLI::App* node = app.add_subcommand("node", "Steer one node through serve: set, preview, identify");
  node->require_subcommand(1);
  auto api = std::make_shared<std::string>();
  auto id = std::make_shared<uint32_t>(0);
  AddApiOption(*node, api.get());
  node->add_option("id", *id, "Node id")->required()->check(CLI::Range(1u, 4294967295u));
  auto path = [id](const std::string& tail) { return "/api/nodes/" + std::to_string(*id) + tail; };

  auto settings = std::make_shared<std::vector<std::string>>();
  CLI::App* set = node->add_subcommand(
      "set", "Change camera settings: threshold=N|auto exposure-us=N gain-milli=N brightness=PCT contrast=PCT");
  set->add_option("settings", *settings, "KEY=VALUE ...")->required();
  set->callback([api, settings, path] {
    const json answer = CallApiJson(*api, "POST", path("/settings"), SettingsBody(*settings));
    std::printf("node %s: %s%s\n", Str(answer, "node").c_str(), Str(answer, "outcome").c_str(),
                answer.value("reason", "").empty() ? "" : (" (" + answer["reason"].get<std::string>() + ")").c_str());
  });

  auto output = std::make_shared<std::string>();
  auto mode = std::make_shared<std::string>("raw");
  auto downscale = std::make_shared<int>(2);
  CLI::App* preview = node->add_subcommand("preview", "Fetch the camera's image as PNG");
  preview->add_option("-o,--output", *output, "PNG file to write")->required();
  preview->add_option("--mode", *mode, "raw or thresholded")->check(CLI::IsMember({"raw", "thresholded"}))->capture_default_str();
  preview->add_option("--downscale", *downscale, "1, 2, 4 or 8")->check(CLI::IsMember({1, 2, 4, 8}))->capture_default_str();
  preview->callback([api, output, mode, downscale, path] {
    const ApiAnswer answer = CallApi(*api, "GET", path("/preview?mode=" + *mode + "&downscale=" + std::to_string(*downscale)));
    if (answer.status != 200) {
      const json error = json::parse(answer.body, nullptr, false);
      throw std::runtime_error((error.is_object() && error.contains("error") ? error["error"].dump() : answer.body) +
                               " (HTTP " + std::to_string(answer.status) + ")");
    }
    std::ofstream out(*output, std::ios::binary);
    out.write(answer.body.data(), static_cast<std::streamsize>(answer.body.size()));
    out.close();
    if (!out) throw std::runtime_error(*output + ": cannot write");
    std::printf("%s: %zu bytes\n", output->c_str(), answer.body.size());
  });

  auto duration = std::make_shared<int>(3000);
  CLI::App* identify = node->add_subcommand("identify", "Blink the node's LED (or log a notice on it)");
  identify->add_option("--duration-ms", *duration, "How long")->check(CLI::Range(100, 60000))->capture_default_str();
  identify->callback([api, duration, path] {
    const json answer = CallApiJson(*api, "POST", path("/identify"), json{{"duration_ms", *duration}});
    std::printf("node %s: %s\n", Str(answer, "node").c_str(), Str(answer, "outcome").c_str());
  });
}

// `mask auto|clear`.
void AddMaskCommand(CLI::App& app) {
  CLI::App* mask = app.add_subcommand("mask", "Camera masks for static reflections, through serve");
  mask->require_subcommand(1);
  auto api = std::make_shared<std::string>();
  AddApiOption(*mask, api.get());
  auto frames = std::make_shared<int>(100);
  CLI::App* automatic = mask->add_subcommand("auto", "Mask what every camera keeps seeing (empty the volume first)");
  automatic->add_option("--frames", *frames, "Frame sets to look at")->check(CLI::Range(10, 100000))->capture_default_str();
  automatic->callback([api, frames] {
    const json answer = CallApiJson(*api, "POST", "/api/masks/auto", json{{"frames", *frames}});
    for (const json& camera : answer["cameras"])
      std::printf("camera %s: %s static blobs found, %s masked regions\n", Str(camera, "camera_id").c_str(),
                  Str(camera, "static_blobs_found").c_str(), Str(camera, "regions").c_str());
    for (const json& node : answer["nodes"])
      std::printf("node %s: %s\n", Str(node, "node").c_str(), Str(node, "outcome").c_str());
  });
  CLI::App* clear = mask->add_subcommand("clear", "Remove every camera's mask");
  clear->callback([api] {
    const json answer = CallApiJson(*api, "DELETE", "/api/masks");
    for (const json& node : answer["nodes"])
      std::printf("node %s: %s\n", Str(node, "node").c_str(), Str(node, "outcome").c_str());
  });
}

// `capture start|stop`.
void AddCaptureCommand(CLI::App& app) {
  CLI::App* capture = app.add_subcommand("capture", "Start or stop a capture in serve");
  capture->require_subcommand(1);
  auto api = std::make_shared<std::string>();
  AddApiOption(*capture, api.get());
  auto name = std::make_shared<std::string>();
  CLI::App* start = capture->add_subcommand("start", "Capture a named session");
  start->add_option("name", *name, "Session name (letters, digits, . - _)")->required();
  start->callback([api, name] {
    const json answer = CallApiJson(*api, "POST", "/api/capture/start", json{{"name", *name}});
    std::printf("capturing %s -> %s\n", Str(answer, "name").c_str(), Str(answer, "path").c_str());
  });
  CLI::App* stop = capture->add_subcommand("stop", "Stop the running capture");
  stop->callback([api] {
    const json answer = CallApiJson(*api, "POST", "/api/capture/stop");
    std::printf("%s: %s frame sets in %.1f s -> %s\n", Str(answer, "name").c_str(), Str(answer, "frame_sets").c_str(),
                answer["seconds"].get<double>(), Str(answer, "path").c_str());
  });
}

// `sessions`: what serve has captured.
void AddSessionsCommand(CLI::App& app) {
  auto api = std::make_shared<std::string>();
  auto as_json = std::make_shared<bool>(false);
  CLI::App* c = app.add_subcommand("sessions", "The sessions serve has captured");
  AddApiOption(*c, api.get());
  c->add_flag("--json", *as_json, "Print the JSON answer");
  c->callback([api, as_json] {
    const json list = CallApiJson(*api, "GET", "/api/sessions");
    if (*as_json) return Print(list);
    for (const json& s : list)
      std::printf("%-24s %-12s %8s frame sets  %s\n", Str(s, "name").c_str(), Str(s, "state").c_str(),
                  Str(s, "frame_sets").c_str(), Str(s, "path").c_str());
  });
}

}  // namespace

void AddServiceClientCommands(CLI::App& app) {
  AddStatusCommand(app);
  AddNodesCommand(app);
  AddNodeCommand(app);
  AddMaskCommand(app);
  AddCaptureCommand(app);
  AddSessionsCommand(app);
}

}  // namespace mocap
