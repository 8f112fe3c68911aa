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
// each client has its own writer thread, so one that stops reading stalls only itself. At most
// kMaxWebSocketClients at once.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "api/static_files.h"
#include "service/hub_service.h"
#include "stream/frame_queue.h"

struct mg_context;
struct mg_connection;

namespace mocap::api {

class HttpServer {
 public:
  // listen: "HOST:PORT" (port 0: any free one); console: where the web console's files are
  // (none: the API only). Starts serving at once; throws std::runtime_error when the address
  // cannot be bound.
  HttpServer(service::HubService& service, const std::string& listen, std::vector<StaticMount> console = {});
  ~HttpServer();
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  uint16_t port() const { return port_; }
  // From the hub's loop (its one subscription fans out to every adapter).
  void Publish(stream::SharedFrame frame) { queue_.Push(std::move(frame)); }

  static constexpr size_t kMaxWebSocketClients = 64;

  // civetweb callbacks (public for the C trampolines only).
  int OnRequest(mg_connection* connection);
  int OnStaticRequest(mg_connection* connection);
  bool AcceptWebSocket(const mg_connection* connection);
  void OnWebSocketReady(mg_connection* connection);
  void OnWebSocketClose(const mg_connection* connection);

 private:
  struct Client;
  void Broadcast();
  static void Write(Client* client);

  service::HubService& service_;
  std::vector<StaticMount> console_;
  mg_context* context_ = nullptr;
  uint16_t port_ = 0;
  stream::FrameQueue queue_;
  std::atomic<bool> stopping_{false};
  std::mutex clients_mutex_;  // clients_
  std::map<mg_connection*, std::unique_ptr<Client>> clients_;
  std::thread broadcaster_;
};

}  // namespace mocap::api
