// The live hub's HTTP + WebSocket edge on civetweb (Debian's libcivetweb: a small embeddable C
// server with WebSockets built in, already packaged for every target, no Boost): requests go
// to HandleApiRequest, and /api/live streams every published frame to WebSocket clients as
// JSON text messages:
//   {"frame": N, "trigger_ns": T, "publish_ns": P, "cameras": C,
//    "points": [[x, y, z, id, provisional, views, rms_px], ...]}
// (mm, world frame; id is the confirmed marker number or, when provisional is 1, the tentative
// track's serial, -1 for a point no track took). A client that cannot keep up loses frames, never
// the service: each keeps at most a few frames queued.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <thread>

#include "service/hub_service.h"

struct mg_context;
struct mg_connection;

namespace mocap::service {

class HttpServer {
 public:
  // listen: "HOST:PORT" (port 0: any free one). Starts serving at once; throws
  // std::runtime_error when the address cannot be bound.
  HttpServer(HubService& service, const std::string& listen);
  ~HttpServer();
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  uint16_t port() const { return port_; }

  // civetweb callbacks (public for the C trampolines only).
  int OnRequest(mg_connection* connection);
  void OnWebSocketReady(mg_connection* connection);
  void OnWebSocketClose(const mg_connection* connection);

 private:
  void Broadcast();

  HubService& service_;
  mg_context* context_ = nullptr;
  uint16_t port_ = 0;

  std::mutex mutex_;  // outbox_, subscription_, stopping_
  std::condition_variable wake_;
  std::deque<std::string> outbox_;  // serialised frames waiting for the broadcaster
  std::mutex clients_mutex_;  // clients_, held while writing to them
  std::set<mg_connection*> clients_;
  bool subscribed_ = false;
  int subscription_ = 0;
  bool stopping_ = false;
  std::thread broadcaster_;
};

}  // namespace mocap::service
