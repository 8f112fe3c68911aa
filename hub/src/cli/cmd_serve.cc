// `serve`: the live hub as a long-running service (service/hub_service.h) with its HTTP +
// WebSocket API (api/http_server.h) and its streams, which the service wires
// (service/stream_fan_out.h; the WebSockets get each frame from there). Options come from flags and/or a config file
// (--config FILE, `key = value`, one line per long option name; cli/config_file.h); flags win. Under systemd
// (Type=notify) it reports READY=1 once both sockets are bound, pings the watchdog from the
// loop itself, so a stuck loop gets the service restarted, and STOPPING=1 on the way out.
#include <atomic>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <vector>
#include <string>

#include "cli/commands.h"
#include "cli/config_file.h"
#include "ingest/udp_socket.h"
#include "api/api_tokens.h"
#include "api/http_server.h"
#include "api/static_files.h"
#include "service/hub_service.h"
#include "service/stream_fan_out.h"
#include "util/log.h"

#ifdef MOCAP_HAVE_SYSTEMD
#include <systemd/sd-daemon.h>
#endif

namespace mocap {
namespace {

std::atomic<bool> g_stop{false};
void OnSignal(int) { g_stop.store(true); }

struct ServeArgs {
  service::ServeOptions options;
  std::string api = "127.0.0.1:7801";
  std::string api_auth;                // the tokens' directory, or "off"; default beside the sessions
  bool insecure_dev_api = false;
  std::vector<std::string> api_host_names;
  int api_threads = 384;
  int api_request_timeout_ms = 3000;
  size_t api_max_websockets = 64;
  service::StreamsOptions streams;     // the streams' own options; serve's rate and files from `options`
  std::string web_root = MOCAP_WEB_ROOT;  // the console's files; "off": none
  std::string three_root = "/usr/share/javascript/three";  // Debian's libjs-three
};

// The console's files: a missing directory is a usage error when asked for explicitly, and a
// warning for the built-in default (an installation that copied only the binary still serves
// its API).
std::vector<api::StaticMount> ConsoleOf(const ServeArgs& args, bool web_root_given) {
  if (args.web_root == "off") return {};
  std::vector<api::StaticMount> mounts = api::ConsoleMounts(args.web_root, args.three_root);
  const bool has_root = !mounts.empty() && mounts[0].prefix == "/";
  if (!has_root && web_root_given) throw UsageError("--web-root " + args.web_root + ": not a directory");
  if (!has_root) {
    log::Warn("web console not served: {} is not a directory (--web-root)", args.web_root);
    return {};
  }
  if (mounts.size() < 2)
    log::Warn("web console without its 3D views: {} missing (Debian package libjs-three)", args.three_root);
  return mounts;
}

// Watchdog pings at half the interval systemd asks for; nothing without systemd.
class Watchdog {
 public:
  Watchdog() {
#ifdef MOCAP_HAVE_SYSTEMD
    uint64_t usec = 0;
    if (sd_watchdog_enabled(0, &usec) > 0) interval_ns_ = usec * 1000 / 2;
#endif
  }
  void Notify(const std::string& state) {
#ifdef MOCAP_HAVE_SYSTEMD
    sd_notify(0, state.c_str());
#else
    (void)state;
#endif
  }
  void Ping(uint64_t now_ns) {
    if (!interval_ns_ || now_ns < next_ns_) return;
    next_ns_ = now_ns + interval_ns_;
    Notify("WATCHDOG=1");
  }

 private:
  uint64_t interval_ns_ = 0;
  uint64_t next_ns_ = 0;
};

bool IsLoopback(const std::string& host) {
  return host == "localhost" || host == "::1" || host.rfind("127.", 0) == 0;
}

// The API's access (api/access.h): tokens in --api-auth DIR (default api-auth beside the
// sessions directory); at the first start a token for the local operator is issued into
// DIR/operator.token, which the CLI on this machine reads. Without tokens (off, or
// --insecure-dev-api) the API may listen on loopback only, unless told --insecure-dev-api.
api::HttpServerOptions HttpOptionsOf(const ServeArgs& args, std::vector<api::StaticMount> console) {
  namespace fs = std::filesystem;
  api::HttpServerOptions http;
  http.listen = args.api;
  http.console = std::move(console);
  http.threads = args.api_threads;
  http.request_timeout_ms = args.api_request_timeout_ms;
  http.max_websockets = args.api_max_websockets;
  http.access.host_names = args.api_host_names;
  const HostPort address = ParseHostPort(args.api);
  const bool loopback = IsLoopback(address.host);
  http.access.tokens_required = args.api_auth != "off" && !args.insecure_dev_api;
  if (!http.access.tokens_required) {
    if (!loopback && !args.insecure_dev_api)
      throw UsageError("--api-auth off with --api " + args.api +
                       ": the API would be open to the network; keep tokens, or bind it to 127.0.0.1, or say "
                       "--insecure-dev-api");
    log::Warn("{}API WITHOUT TOKENS: anyone who reaches {} steers this hub (captures, thresholds, calibration)",
              args.insecure_dev_api ? "INSECURE DEVELOPMENT " : "", args.api);
    if (const std::string error = http.Check(); !error.empty()) throw UsageError(error);
    return http;
  }
  fs::path sessions = fs::path(args.options.sessions_dir).lexically_normal();
  if (!sessions.has_filename()) sessions = sessions.parent_path();  // "x/sessions/"
  const fs::path dir = args.api_auth.empty() ? sessions.parent_path() / "api-auth" : fs::path(args.api_auth);
  std::error_code ec;
  if (fs::create_directories(dir, ec)) fs::permissions(dir, fs::perms::owner_all, fs::perm_options::replace, ec);
  if (!fs::is_directory(dir)) throw std::runtime_error(dir.string() + ": cannot create the API tokens' directory");
  http.token_store = (dir / "tokens").string();
  http.logins_file = (dir / "logins.json").string();
  if (api::ReadTokenStore(http.token_store).empty()) {
    const std::string holder = (dir / "operator.token").string();
    api::IssueToken(http.token_store, "local", api::ApiRole::kOperator, holder);
    log::Info("API token 'local' (operator) issued into {}: the CLI reads it (MOCAP_HUB_TOKEN_FILE), the console "
              "logs in with its content; `mocap-hub tokens` issues more",
              holder);
  }
  if (const std::string error = http.Check(); !error.empty()) throw UsageError(error);
  return http;
}

void RunServe(ServeArgs& args, bool web_root_given) {
  if (args.options.sessions_dir.empty()) throw UsageError("--sessions-dir must name a directory");
  CheckOptions(args.options);
  try {
    args.streams.Check(args.options);
  } catch (const std::invalid_argument& error) {
    throw UsageError(error.what());
  }
  std::vector<api::StaticMount> console = ConsoleOf(args, web_root_given);
  api::HttpServerOptions http_options = HttpOptionsOf(args, std::move(console));
  // Processing jobs run this very program as `process` (service/processing_jobs.h).
  std::error_code self_error;
  args.options.processing_executable = std::filesystem::read_symlink("/proc/self/exe", self_error).string();
  if (self_error) log::Warn("processing jobs: cannot find this program ({}); the console cannot process sessions",
                            self_error.message());
  service::HubService hub(args.options);
  hub.Bind();
  api::HttpServer http(hub, http_options);
  // The streams on the hub's frames and captures; the WebSockets get each frame from them too.
  service::StreamFanOut streams(args.options, args.streams, hub,
                                [&http](stream::SharedFrame frame) { http.Publish(std::move(frame)); });
  std::signal(SIGINT, OnSignal);
  std::signal(SIGTERM, OnSignal);
  std::signal(SIGPIPE, SIG_IGN);
  const HostPort api = ParseHostPort(args.api);
  const std::string api_host = api.host.empty() || api.host == "*" ? "0.0.0.0" : api.host;
  log::Info("serving: UDP port {} for the nodes, API http://{}:{}, sessions in {}", hub.port(), api_host, http.port(),
            args.options.sessions_dir);
  if (!http_options.console.empty())
    log::Info("web console at http://{}:{}/ from {}", api_host, http.port(), http_options.console[0].dir);
  for (const std::string& where : streams.Where()) log::Info("{}", where);
  Watchdog watchdog;
  watchdog.Notify("READY=1\nSTATUS=serving on UDP " + std::to_string(hub.port()));
  hub.Run(g_stop, [&watchdog](uint64_t now_ns) { watchdog.Ping(now_ns); });
  watchdog.Notify("STOPPING=1");
  log::Info("stopped");
}

// The API's address, its access and its bounds.
void AddApiOptions(CLI::App* command, ServeArgs& args) {
  command->add_option("--api", args.api,
                      "HOST:PORT of the HTTP/WebSocket API (tokens required; beyond localhost put a TLS reverse "
                      "proxy in front, docs/security.md)")
      ->capture_default_str();
  command->add_option("--api-auth", args.api_auth,
                      "Directory of the API's tokens (`mocap-hub tokens`; default api-auth beside the sessions "
                      "directory, its operator.token issued at the first start), or off (loopback only)");
  command->add_flag("--insecure-dev-api", args.insecure_dev_api,
                    "DEVELOPMENT ONLY: no API tokens, on any address (anyone who reaches it steers the hub)");
  command->add_option("--api-host-name", args.api_host_names,
                      "A name of this hub browsers may use (Host header), besides IP addresses and localhost");
  command->add_option("--api-threads", args.api_threads, "HTTP worker threads (each connection holds one)")
      ->capture_default_str();
  command->add_option("--api-request-timeout-ms", args.api_request_timeout_ms,
                      "A request (head, then body) must arrive within this; idle connections are closed then")
      ->capture_default_str();
  command->add_option("--api-max-websockets", args.api_max_websockets,
                      "WebSocket clients at once (each holds a worker; more are refused with 503)")
      ->capture_default_str();
}

// The nodes' side: where they send, the calibration naming them, the captures, the session's
// rate and what each frame is told (bodies, labels).
void AddSessionOptions(CLI::App* command, service::ServeOptions& o) {
  command->add_option("--listen", o.listen, "HOST:PORT receiving the nodes' UDP")->capture_default_str();
  // Required, but checked in ServeOptions::Check: it may come from the config file.
  command->add_option("--calibration", o.calibration, "Calibration JSON (names the cameras); required")
      ->check(CLI::ExistingFile);
  command->add_option("--sessions-dir", o.sessions_dir, "Where captures go (one directory per session)")
      ->capture_default_str();
  command->add_option("--capture-min-free-mb", o.disk.start_free_mb,
                      "A capture starts only with this much free on the sessions disk (MiB)")
      ->capture_default_str();
  command->add_option("--capture-warn-free-mb", o.disk.warn_free_mb,
                      "Warn (log, /api/status sessions_disk) below this much free (MiB)")
      ->capture_default_str();
  command->add_option("--capture-stop-free-mb", o.disk.stop_free_mb,
                      "A running capture ends `failed: disk full` below this much free (MiB); serve goes on")
      ->capture_default_str();
  command->add_option("--masks-file", o.masks_file, "The installation's camera masks (JSON), kept and re-sent");
  command->add_option("--labels", o.labels_file,
                      "Marker set (JSON, `mocap-hub labels learn`): names on the published points")
      ->check(CLI::ExistingFile);
  command->add_option("--bodies", o.bodies_file, "Rigid bodies file (JSON, `mocap-hub body define`)")
      ->check(CLI::ExistingFile);
  command->add_option("--skeleton", o.skeleton_file,
                      "A calibrated subject (JSON, `mocap-hub skeleton calibrate`) solved on every frame's named "
                      "markers (needs --labels): bones in /api/live and the streams")
      ->check(CLI::ExistingFile);
  command->add_option("--skeleton-up", o.skeleton_up, "The calibration's up axis for --skeleton: x, y, z, -x, -y, -z")
      ->capture_default_str();
  command->add_option("--bodies-window", o.body_filter.past_frames,
                      "Rigid bodies: each orientation refitted over this frame and up to this many before it, "
                      "fewer where the motion disagrees with the model (0: each frame alone)")
      ->check(CLI::Range(0, 100))
      ->capture_default_str();
  command->add_option("--bodies-degree", o.body_filter.degree,
                      "Rigid bodies: degree of the orientation's polynomial over that window")
      ->check(CLI::Range(1, 3))
      ->capture_default_str();
  command->add_option("--rate", o.rate_hz, "Trigger rate, Hz")->capture_default_str();
  command->add_option("--epoch-ns", o.epoch_ns, "Session epoch (time of frame 0), ns; default: start time")
      ->check(CLI::Range(uint64_t{0}, uint64_t{1} << 62));  // "-1" would wrap to 2^64-1
  command->add_option("--announce", o.announce, "Broadcast HubAnnounce to BROADCAST:PORT every second");
}

// The wire's keys and how the loop waits for and groups the nodes' datagrams.
void AddWireOptions(CLI::App* command, service::ServeOptions& o) {
  command->add_option("--keys", o.auth.keys_dir,
                      "Directory of the nodes' wire keys (node-N.key, `mocap-hub keys new`); required unless "
                      "--insecure-dev-wire")
      ->check(CLI::ExistingDirectory);
  command->add_flag("--insecure-dev-wire", o.auth.insecure_dev,
                    "DEVELOPMENT ONLY: no keys, unauthenticated datagrams (anyone on the network can forge "
                    "frames and steer the nodes)");
  command->add_option("--busy-poll-us", o.busy_poll_us,
                      "While a frame set arrives, poll without sleeping for up to this long after each datagram "
                      "(lower latency for CPU time; 0 sleeps at once)")
      ->capture_default_str();
  command->add_option("--realtime-priority", o.realtime_priority,
                      "Run the frame loop under SCHED_FIFO at this priority (1-99; 0: off): nothing ordinary on its "
                      "core delays a frame set. Needs root, CAP_SYS_NICE or LimitRTPRIO= (deploy/mocap-hub.service)")
      ->capture_default_str();
  command->add_option("--deadline-ms", o.deadline_ms, "How long a frame set waits for late cameras")
      ->capture_default_str();
  command->add_flag("--free-run", o.free_run, "No trigger wire: group frames by capture time");
  command->add_option("--node-lost-after", o.node_lost_after_s, "Seconds of silence before a node is lost")
      ->capture_default_str();
  command->add_option("--request-timeout", o.request_timeout_s, "Seconds a node has to answer a request")
      ->capture_default_str();
}

// The live reconstruction and tracking (as `reconstruct` takes them) and the calibration monitor.
void AddReconOptions(CLI::App* command, service::ServeOptions& o) {
  command->add_option("--contested-gate-factor", o.recon.prediction.contested_gate_factor,
                      "Predictions nearer each other than this times the sum of their gates (each counted up to "
                      "30 mm) are left to the matcher (dense clusters); 0 serves every prediction")
      ->capture_default_str();
  command->add_option("--threads", o.recon.threads,
                      "Worker threads inside a frame (undistortion, blob index, predictions); results are identical "
                      "for any count")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  command->add_option("--max-ray-distance-mm", o.recon.graph.max_ray_distance_mm,
                      "Epipolar gate of live reconstruction (as reconstruct's: at least; widens with the noise)")
      ->capture_default_str();
  AddRigOptions(*command, &o.recon, &o.tracker);
  command->add_flag("!--no-calibration-monitor", o.calibration_monitor,
                    "Do not watch the cameras' residuals for bumps (on by default: a moved camera is reported and "
                    "re-solved, /api/status calibration_monitor)");
}

// The streams (service/stream_fan_out.h); returns --stream, whose default follows --api.
CLI::Option* AddStreamOptions(CLI::App* command, service::StreamsOptions& s) {
  CLI::Option* stream = command->add_option(
      "--stream", s.stream.listen,
      "HOST:PORT of the live stream (subscriptions in, frames out); off: none; default port 7802 on the API's "
      "address");
  command->add_option("--stream-multicast", s.stream.multicast,
                      "Also send every frame to this multicast GROUP:PORT (e.g. 239.255.42.1:7803)");
  command->add_option("--stream-multicast-parts", s.stream_multicast_parts,
                      "Parts of the multicast frames: points,bodies,labels,bones")
      ->capture_default_str();
  command->add_option("--osc", s.osc_targets, "Send OSC bundles per frame to HOST:PORT[,HOST:PORT...]");
  command->add_option("--osc-parts", s.osc_parts, "Parts of the OSC bundles: points,bodies,bones")
      ->capture_default_str();
  command->add_option("--qtm-rt", s.qtm_rt,
                      "HOST:PORT of a Qualisys-RT-compatible server (little-endian port; 0: any free); default off");
  command->add_option("--natnet", s.natnet.listen,
                      "HOST:PORT of an OptiTrack-NatNet-compatible command port (Motive's is 1510; 0: any free); "
                      "default off");
  command->add_option("--natnet-multicast", s.natnet.multicast, "NatNet frames' multicast group")
      ->capture_default_str();
  command->add_option("--natnet-data-port", s.natnet.data_port, "NatNet frames' port (the group's)")
      ->capture_default_str();
  command->add_flag("--natnet-unicast", s.natnet_unicast,
                    "NatNet frames by unicast to each connected client instead of multicast");
  command->add_option("--natnet-version", s.natnet.version,
                      "NatNet bitstream version until a client asks another: 3.0, 3.1, 4.0, 4.1")
      ->capture_default_str();
  command->add_option("--vrpn", s.vrpn.listen,
                      "HOST:PORT of a VRPN tracker server, one tracker per rigid body (VRPN's port is 3883; TCP and "
                      "the UDP lookup); default off");
  command->add_flag("--vrpn-velocity", s.vrpn.velocity, "VRPN: also vrpn_Tracker Velocity reports");
  command->add_option("--vmc", s.vmc, "Send rigid bodies as VMC trackers and the --skeleton as VMC bones (OSC) to HOST:PORT (receivers: 39539)");
  return stream;
}

}  // namespace

void AddServeCommand(CLI::App& app) {
  CLI::App* command = app.add_subcommand(
      "serve", "Run the live hub: node registry and control, captures, live 3D, HTTP/WebSocket API");
  auto args = std::make_shared<ServeArgs>();
  auto config = std::make_shared<std::string>();
  command->add_option("--config", *config, "Config file: `key = value` per long option name; flags win")
      ->check(CLI::ExistingFile);
  AddSessionOptions(command, args->options);
  AddApiOptions(command, *args);
  AddWireOptions(command, args->options);
  AddReconOptions(command, args->options);
  CLI::Option* stream = AddStreamOptions(command, args->streams);
  CLI::Option* web_root = command->add_option("--web-root", args->web_root,
                                              "Directory of the web console's files (hub/web); off: API only")
                              ->capture_default_str();
  command->add_option("--three-root", args->three_root, "three.js for the console's 3D views (libjs-three)")
      ->capture_default_str();
  command->callback([args, config, command, web_root, stream] {
    if (!config->empty()) ApplyConfigFile(*command, *config);
    // The stream listens where the API does unless told otherwise: a hub kept on localhost keeps
    // its stream there too.
    if (stream->count() == 0) {
      const HostPort api = ParseHostPort(args->api);
      args->streams.stream.listen = (api.host.empty() ? std::string("0.0.0.0") : api.host) + ":7802";
    }
    RunServe(*args, web_root->count() > 0);
  });
}

}  // namespace mocap
