// The live hub's HTTP + WebSocket edge on civetweb (Debian's libcivetweb: a small embeddable C
// server with WebSockets built in, already packaged for every target, no Boost): requests go
// to the service's router (service/api_router.h), and two WebSockets carry every published
// frame:
//   /api/live    JSON text messages, one per frame:
//     {"frame": N, "trigger_ns": T, "publish_ns": P, "cameras": C,
//      "points": [[x, y, z, id, provisional, views, rms_px], ...],
//      "bodies": [[id, tracked, predicted, x, y, z, qx, qy, qz, qw, mean_error_mm, markers], ...]}
//     (mm, world frame; id is the confirmed marker number or, when provisional is 1, the
//     tentative track's serial, -1 for a point no track took)
//     /api/live?max_fps=N sends at most N frames per second (api/live_query.h).
//   /api/stream  binary messages, one StreamFrame (proto/mocap_stream.proto) per frame, with the
//     parts asked for in the query: /api/stream?parts=points,bodies (default points,bodies).
// Every other path is the web console's static files (api/static_files.h; GET and HEAD, with an
// ETag so a reload costs a 304), answered from the HTTP worker threads; a session file a request
// names (/api/sessions/NAME/files/FILE) is streamed from disk in 64 KiB pieces, never held whole.
// A client that cannot keep up loses frames, nobody else's and never the service's: the
// broadcaster thread hands each frame to every client's short queue (dropping the oldest), and
// each client has its own writer thread, so one that stops reading stalls only itself.
// Access (api/access.h): every /api request and WebSocket passes the Host, Origin and CSRF rules
// and then needs a token or a console login (POST /api/login, POST /api/logout, GET /api/whoami
// are answered here); the console's files need only the Host rule (the login page is one).
// Staying up: civetweb gives each connection a worker thread for its life, so there are many
// (`threads`), a request must arrive whole within `request_timeout_ms` (idle and slow-header
// connections are dropped then) and its body within the same again; WebSockets, which hold their
// worker, are capped at `max_websockets`, well below the workers, and one more is refused with a
// 503 that says so.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "api/access.h"
#include "api/static_files.h"
#include "service/hub_service.h"
#include "stream/frame_queue.h"

struct mg_context;
struct mg_connection;

namespace mocap::api {

struct HttpServerOptions {
  std::string listen = "127.0.0.1:7801";  // HOST:PORT (port 0: any free one)
  std::vector<StaticMount> console;       // the web console's files (none: the API only)
  AccessOptions access;
  std::string token_store;                // api_tokens.h; needed when access.tokens_required
  std::string logins_file;                // the console's logins, kept across restarts ("": none)
  int threads = 384;
  int request_timeout_ms = 3000;
  size_t max_websockets = 64;

  // "" or the refusal naming the field, its value and the rule.
  std::string Check() const;
};

class HttpServer {
 public:
  // Starts serving at once; throws std::runtime_error when the address cannot be bound or the
  // token store cannot be read.
  HttpServer(service::HubService& service, HttpServerOptions options);
  ~HttpServer();
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  uint16_t port() const { return port_; }
  // From the hub's loop (its one subscription fans out to every adapter).
  void Publish(stream::SharedFrame frame) { queue_.Push(std::move(frame)); }

  // civetweb callbacks (public for the C trampolines only).
  int OnRequest(mg_connection* connection);
  int OnStaticRequest(mg_connection* connection);
  // 0 to accept the upgrade; else the refusal's status, already written to the client.
  int AcceptWebSocket(const mg_connection* connection);
  void OnWebSocketReady(mg_connection* connection);
  void OnWebSocketClose(const mg_connection* connection);

 private:
  struct Client;
  void Broadcast();
  static void Write(Client* client);
  AccessDecision Decide(const mg_connection* connection, bool websocket);
  // /api/login, /api/logout, /api/whoami: answered here (they are about the connection's caller).
  bool AnswerSession(mg_connection* connection, const std::string& path, const std::string& body,
                     const AccessDecision& access, int* status);

  service::HubService& service_;
  HttpServerOptions options_;
  std::unique_ptr<TokenVerifier> tokens_;
  LoginSessions sessions_;
  mg_context* context_ = nullptr;
  uint16_t port_ = 0;
  stream::FrameQueue queue_;
  std::atomic<bool> stopping_{false};
  std::mutex clients_mutex_;  // clients_
  std::map<mg_connection*, std::unique_ptr<Client>> clients_;
  size_t upgrading_ = 0;  // accepted upgrades not yet ready
  std::thread broadcaster_;
};

}  // namespace mocap::api
