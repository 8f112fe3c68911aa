// civetweb adapter of the live hub's API (see http_server.h).
#include "api/http_server.h"

#include <civetweb.h>

#include <cstring>
#include <stdexcept>
#include <vector>

#include "ingest/udp_socket.h"
#include "service/api_router.h"
#include "stream/stream_encoding.h"
#include "util/log.h"

namespace mocap::api {

using service::LiveFrame;
using service::LivePoint;
using service::ApiRequest;
using service::ApiResponse;
using service::kMaxApiBody;
namespace {

constexpr size_t kMaxQueuedFrames = 4;

HttpServer* ServerOf(const mg_connection* connection) {
  return static_cast<HttpServer*>(mg_get_user_data(mg_get_context(connection)));
}

int RequestTrampoline(mg_connection* connection, void*) { return ServerOf(connection)->OnRequest(connection); }
// The parts a /api/stream client asked for (its query's parts=...); 0 when the list is bad.
uint32_t PartsOf(const mg_connection* connection) {
  const mg_request_info* info = mg_get_request_info(connection);
  const char* query = info->query_string ? info->query_string : "";
  char value[64];
  if (mg_get_var(query, std::strlen(query), "parts", value, sizeof value) < 0) return stream::kDefaultParts;
  try {
    return stream::ParseParts(value);
  } catch (const std::invalid_argument&) {
    return 0;
  }
}

bool IsStream(const mg_connection* connection) {
  const char* uri = mg_get_request_info(connection)->local_uri;
  return uri && std::strcmp(uri, "/api/stream") == 0;
}

// Refuses (non-zero) a /api/stream upgrade with an unknown part, and any beyond the client limit.
int WebSocketConnect(const mg_connection* connection, void*) {
  return (IsStream(connection) && !PartsOf(connection)) || !ServerOf(connection)->AcceptWebSocket(connection);
}
void WebSocketReady(mg_connection* connection, void*) { ServerOf(connection)->OnWebSocketReady(connection); }
int WebSocketData(mg_connection*, int, char*, size_t, void*) { return 1; }  // keep open, ignore input
void WebSocketClose(const mg_connection* connection, void*) { ServerOf(connection)->OnWebSocketClose(connection); }

const char* Reason(int status) {
  switch (status) {
    case 200: return "OK";
    case 400: return "Bad Request";
    case 404: return "Not Found";
    case 405: return "Method Not Allowed";
    case 409: return "Conflict";
    case 413: return "Payload Too Large";
    case 503: return "Service Unavailable";
    case 504: return "Gateway Timeout";
    default: return status >= 500 ? "Internal Server Error" : "Error";
  }
}

// A JSON string's content: quotes, backslashes and control characters escaped.
std::string JsonEscaped(const std::string& text) {
  std::string out;
  for (const char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char code[8];
      std::snprintf(code, sizeof code, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
      out += code;
    } else {
      out += c;
    }
  }
  return out;
}

std::string FrameMessage(const LiveFrame& frame) {
  std::string out;
  out.reserve(64 + frame.points.size() * 64);
  char buffer[256];
  std::snprintf(buffer, sizeof(buffer), "{\"frame\":%llu,\"trigger_ns\":%llu,\"publish_ns\":%llu,\"cameras\":%d,\"points\":[",
                static_cast<unsigned long long>(frame.frame_number),
                static_cast<unsigned long long>(frame.trigger_time_ns),
                static_cast<unsigned long long>(frame.publish_ns), frame.cameras);
  out += buffer;
  for (size_t i = 0; i < frame.points.size(); ++i) {
    const LivePoint& p = frame.points[i];
    const long long id = p.provisional() ? (p.provisional_track ? static_cast<long long>(p.provisional_track) : -1)
                                         : static_cast<long long>(p.marker);
    std::snprintf(buffer, sizeof(buffer), "%s[%.3f,%.3f,%.3f,%lld,%d,%d,%.3f", i ? "," : "", p.position.x(),
                  p.position.y(), p.position.z(), id, p.provisional() ? 1 : 0, p.views, p.rms_px);
    out += buffer;
    // With a marker set (serve --labels) an eighth element: the point's name, or null.
    if (frame.label_names) {
      if (p.label >= 0 && static_cast<size_t>(p.label) < frame.label_names->size())
        out += ",\"" + JsonEscaped((*frame.label_names)[static_cast<size_t>(p.label)]) + "\"";
      else
        out += ",null";
    }
    out += "]";
  }
  out += "],\"bodies\":[";
  for (size_t i = 0; i < frame.bodies.size(); ++i) {
    const service::LiveBody& b = frame.bodies[i];
    const Eigen::Quaterniond& q = b.orientation;
    std::snprintf(buffer, sizeof(buffer), "%s[%u,%d,%d,%.3f,%.3f,%.3f,%.6f,%.6f,%.6f,%.6f,%.3f,%d]", i ? "," : "", b.id,
                  b.tracked ? 1 : 0, b.predicted ? 1 : 0, b.position.x(), b.position.y(), b.position.z(), q.x(), q.y(),
                  q.z(), q.w(), b.mean_error_mm, b.markers);
    out += buffer;
  }
  out += "]}";
  return out;
}

}  // namespace

struct HttpServer::Client {
  mg_connection* connection = nullptr;
  bool binary = false;   // /api/stream (protobuf) rather than /api/live (JSON)
  uint32_t parts = 0;
  stream::FrameQueue queue{kMaxQueuedFrames};
  std::thread writer;
};

HttpServer::HttpServer(service::HubService& service, const std::string& listen)
    : service_(service), queue_(kMaxQueuedFrames) {
  const HostPort address = ParseHostPort(listen);
  const std::string ports = (address.host.empty() || address.host == "*" ? std::string("0.0.0.0") : address.host) +
                            ":" + std::to_string(address.port);
  mg_init_library(0);
  const char* options[] = {"listening_ports", ports.c_str(), "num_threads", "8", "request_timeout_ms", "15000",
                           "enable_websocket_ping_pong", "yes", nullptr};
  mg_callbacks callbacks;
  std::memset(&callbacks, 0, sizeof(callbacks));
  context_ = mg_start(&callbacks, this, options);
  if (!context_) throw std::runtime_error("HTTP API: cannot listen on " + ports + " (in use, or not an address of this host)");
  mg_server_port bound[4];
  const int n = mg_get_server_ports(context_, 4, bound);
  if (n > 0) port_ = static_cast<uint16_t>(bound[0].port);
  mg_set_request_handler(context_, "/api", RequestTrampoline, nullptr);
  for (const char* path : {"/api/live", "/api/stream"})
    mg_set_websocket_handler(context_, path, WebSocketConnect, WebSocketReady, WebSocketData, WebSocketClose, nullptr);
  broadcaster_ = std::thread([this] { Broadcast(); });
}

HttpServer::~HttpServer() {
  stopping_ = true;
  queue_.Close();
  broadcaster_.join();
  // Closing the connections ends their writers (OnWebSocketClose joins each).
  mg_stop(context_);
  mg_exit_library();
}

int HttpServer::OnRequest(mg_connection* connection) {
  const mg_request_info* info = mg_get_request_info(connection);
  ApiRequest request;
  request.method = info->request_method ? info->request_method : "";
  request.path = info->local_uri ? info->local_uri : "";
  request.query = info->query_string ? info->query_string : "";
  ApiResponse response;
  if (request.path == "/api/live" || request.path == "/api/stream") {
    response.status = 400;
    response.body = "{\"error\":\"" + request.path + " is a WebSocket: connect with an Upgrade request\"}";
  } else if (info->content_length > static_cast<long long>(kMaxApiBody)) {
    response.status = 413;
    response.body = R"({"error":"the body is larger than 64 KiB"})";
  } else {
    // Read at most the limit plus one byte, so a lying Content-Length cannot make us buffer more.
    std::vector<char> buffer(kMaxApiBody + 1);
    size_t got = 0;
    int r;
    while (got < buffer.size() && (r = mg_read(connection, buffer.data() + got, buffer.size() - got)) > 0)
      got += static_cast<size_t>(r);
    request.body.assign(buffer.data(), got);
    response = HandleApiRequest(service_, request);
  }
  mg_printf(connection,
            "HTTP/1.1 %d %s\r\nContent-Type: %s\r\nContent-Length: %zu\r\nCache-Control: no-store\r\n"
            "Connection: close\r\n\r\n",
            response.status, Reason(response.status), response.content_type.c_str(), response.body.size());
  mg_write(connection, response.body.data(), response.body.size());
  return response.status;
}

bool HttpServer::AcceptWebSocket(const mg_connection*) {
  std::lock_guard<std::mutex> lock(clients_mutex_);
  return clients_.size() < kMaxWebSocketClients;
}

void HttpServer::OnWebSocketReady(mg_connection* connection) {
  auto client = std::make_unique<Client>();
  client->connection = connection;
  client->binary = IsStream(connection);
  client->parts = client->binary ? PartsOf(connection) : 0;
  client->writer = std::thread(Write, client.get());
  std::lock_guard<std::mutex> lock(clients_mutex_);
  clients_[connection] = std::move(client);
}

void HttpServer::OnWebSocketClose(const mg_connection* connection) {
  std::unique_ptr<Client> client;
  {
    std::lock_guard<std::mutex> lock(clients_mutex_);
    auto it = clients_.find(const_cast<mg_connection*>(connection));
    if (it == clients_.end()) return;
    client = std::move(it->second);
    clients_.erase(it);
  }
  // civetweb frees the connection after this returns: its writer must be done with it.
  client->queue.Close();
  client->writer.join();
}

void HttpServer::Broadcast() {
  while (!stopping_) {
    const stream::SharedFrame frame = queue_.Pop(std::chrono::milliseconds(200));
    if (!frame) continue;
    std::lock_guard<std::mutex> lock(clients_mutex_);
    for (auto& [connection, client] : clients_) client->queue.Push(frame);
  }
}

void HttpServer::Write(Client* client) {
  while (!client->queue.closed()) {
    const stream::SharedFrame frame = client->queue.Pop(std::chrono::seconds(1));
    if (!frame) continue;
    const std::string message =
        client->binary ? stream::EncodeStreamFrame(*frame, client->parts).bytes : FrameMessage(*frame);
    mg_lock_connection(client->connection);
    const int written = mg_websocket_write(client->connection,
                                           client->binary ? MG_WEBSOCKET_OPCODE_BINARY : MG_WEBSOCKET_OPCODE_TEXT,
                                           message.data(), message.size());
    mg_unlock_connection(client->connection);
    if (written <= 0) return;  // gone or timed out: civetweb closes it, and OnWebSocketClose joins
  }
}

}  // namespace mocap::api
