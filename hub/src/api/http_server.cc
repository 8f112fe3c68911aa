// civetweb adapter of the live hub's API (see http_server.h).
#include "api/http_server.h"

#include <civetweb.h>

#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <vector>

#include "api/live_query.h"

#include "ingest/udp_socket.h"
#include "service/api_router.h"
#include "stream/stream_encoding.h"
#include "util/log.h"
#include "util/thread_priority.h"

namespace mocap::api {

using pipeline::LiveFrame;
using pipeline::LivePoint;
using service::ApiRequest;
using service::ApiResponse;
using service::kMaxApiBody;
namespace {

constexpr size_t kMaxQueuedFrames = 4;

HttpServer* ServerOf(const mg_connection* connection) {
  return static_cast<HttpServer*>(mg_get_user_data(mg_get_context(connection)));
}

int RequestTrampoline(mg_connection* connection, void*) { return ServerOf(connection)->OnRequest(connection); }
int StaticTrampoline(mg_connection* connection, void*) { return ServerOf(connection)->OnStaticRequest(connection); }
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

std::optional<LiveQuery> LiveQueryOf(const mg_connection* connection) {
  const char* query = mg_get_request_info(connection)->query_string;
  return ParseLiveQuery(query ? query : "");
}

// Refuses (non-zero) a /api/stream upgrade with an unknown part, a /api/live one with a bad
// query, one the access rules refuse, and any beyond the client limit.
int WebSocketConnect(const mg_connection* connection, void*) {
  const bool bad = IsStream(connection) ? !PartsOf(connection) : !LiveQueryOf(connection);
  return bad || ServerOf(connection)->AcceptWebSocket(connection) != 0;
}
void WebSocketReady(mg_connection* connection, void*) { ServerOf(connection)->OnWebSocketReady(connection); }
int WebSocketData(mg_connection*, int, char*, size_t, void*) { return 1; }  // keep open, ignore input
void WebSocketClose(const mg_connection* connection, void*) { ServerOf(connection)->OnWebSocketClose(connection); }

const char* Reason(int status) {
  switch (status) {
    case 200: return "OK";
    case 304: return "Not Modified";
    case 400: return "Bad Request";
    case 401: return "Unauthorized";
    case 403: return "Forbidden";
    case 408: return "Request Timeout";
    case 421: return "Misdirected Request";
    case 404: return "Not Found";
    case 405: return "Method Not Allowed";
    case 409: return "Conflict";
    case 413: return "Payload Too Large";
    case 503: return "Service Unavailable";
    case 504: return "Gateway Timeout";
    case 507: return "Insufficient Storage";
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
    const long long id = p.id ? static_cast<long long>(p.id) : -1;
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
    const pipeline::LiveBody& b = frame.bodies[i];
    const Eigen::Quaterniond& q = b.orientation;
    std::snprintf(buffer, sizeof(buffer), "%s[%u,%d,%d,%.3f,%.3f,%.3f,%.6f,%.6f,%.6f,%.6f,%.3f,%d]", i ? "," : "", b.id,
                  b.tracked ? 1 : 0, b.predicted ? 1 : 0, b.position.x(), b.position.y(), b.position.z(), q.x(), q.y(),
                  q.z(), q.w(), b.mean_error_mm, b.markers);
    out += buffer;
  }
  out += "],\"skeletons\":[";
  for (size_t i = 0; i < frame.skeletons.size(); ++i) {
    const pipeline::LiveSkeleton& s = frame.skeletons[i];
    out += std::string(i ? "," : "") + "{\"name\":\"" + JsonEscaped(s.model ? s.model->name : "") + "\",\"state\":\"" +
           s.state + "\"";
    std::snprintf(buffer, sizeof(buffer),
                  ",\"solved\":%s,\"markers\":%d,\"rms_mm\":%.3f,\"max_mm\":%.3f,\"solve_ms\":%.3f,\"bones\":[",
                  s.solved ? "true" : "false", s.markers, s.rms_mm, s.max_mm, s.solve_ms);
    out += buffer;
    // Only a solved frame has bones: [name, parent index, x, y, z, qx, qy, qz, qw].
    for (size_t b = 0; s.model && b < s.bones.size() && b < s.model->bones.size(); ++b) {
      const pipeline::LiveBone& bone = s.bones[b];
      const Eigen::Quaterniond& q = bone.orientation;
      out += std::string(b ? "," : "") + "[\"" + JsonEscaped(s.model->bones[b]) + "\"";
      std::snprintf(buffer, sizeof(buffer), ",%d,%.3f,%.3f,%.3f,%.6f,%.6f,%.6f,%.6f]", s.model->parents[b],
                    bone.position.x(), bone.position.y(), bone.position.z(), q.x(), q.y(), q.z(), q.w());
      out += buffer;
    }
    out += "]}";
  }
  out += "]}";
  return out;
}

// Writes a response head. Built with std::string rather than mg_printf: civetweb's workers run on
// the small stacks of Debian's build (about 100 KB), and mg_printf's buffer plus glibc's printf
// machinery took the deepest static-file request over it (a worker crashed once the process's
// static TLS grew by a few hundred bytes).
void WriteHead(mg_connection* connection, const std::string& head) {
  mg_write(connection, head.data(), head.size());
}

std::string Header(const mg_connection* connection, const char* name) {
  const char* value = mg_get_header(connection, name);
  return value ? value : "";
}

void WriteError(mg_connection* connection, int status, const std::string& reason, const std::string& headers = "") {
  const std::string body =
      nlohmann::json{{"error", reason}}.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  WriteHead(connection, "HTTP/1.1 " + std::to_string(status) + " " + Reason(status) +
                            "\r\nContent-Type: application/json\r\nContent-Length: " + std::to_string(body.size()) +
                            "\r\nCache-Control: no-store\r\n" + headers + "Connection: close\r\n\r\n" + body);
}

// The file's bytes as the body of a 200 answer, read in pieces (a session's raw log may be large;
// a file still growing, as a running capture's, is sent as long as it was when opened).
int SendFile(mg_connection* connection, const std::string& path, const std::string& content_type, bool head,
             const std::string& extra_headers) {
  std::ifstream in(path, std::ios::binary);
  struct stat st;
  if (!in || ::stat(path.c_str(), &st) != 0) {
    const std::string body = R"({"error":"the file cannot be read"})";
    WriteHead(connection, "HTTP/1.1 404 Not Found\r\nContent-Type: application/json\r\nContent-Length: " +
                              std::to_string(body.size()) + "\r\nConnection: close\r\n\r\n" + body);
    return 404;
  }
  const long long size = static_cast<long long>(st.st_size);
  WriteHead(connection, "HTTP/1.1 200 OK\r\nContent-Type: " + content_type + "\r\nContent-Length: " +
                            std::to_string(size) + "\r\n" + extra_headers + "Connection: close\r\n\r\n");
  if (head) return 200;
  std::vector<char> buffer(64 * 1024);
  long long left = size;
  while (left > 0 && in) {
    in.read(buffer.data(), static_cast<std::streamsize>(std::min<long long>(left, buffer.size())));
    const std::streamsize got = in.gcount();
    if (got <= 0 || mg_write(connection, buffer.data(), static_cast<size_t>(got)) <= 0) break;
    left -= got;
  }
  return 200;
}

}  // namespace

struct HttpServer::Client {
  mg_connection* connection = nullptr;
  bool binary = false;   // /api/stream (protobuf) rather than /api/live (JSON)
  uint32_t parts = 0;
  std::chrono::nanoseconds min_interval{0};  // /api/live?max_fps
  std::chrono::steady_clock::time_point next_due{};
  stream::FrameQueue queue{kMaxQueuedFrames};
  std::thread writer;
};

std::string HttpServerOptions::Check() const {
  if (threads < 8 || threads > 1000) return "threads: " + std::to_string(threads) + " must be 8..1000";
  if (request_timeout_ms < 100 || request_timeout_ms > 60000)
    return "request_timeout_ms: " + std::to_string(request_timeout_ms) + " must be 100..60000";
  if (max_websockets < 1 || max_websockets + 8 > static_cast<size_t>(threads))
    return "max_websockets: " + std::to_string(max_websockets) + " must be 1.." + std::to_string(threads - 8) +
           " (8 workers stay free for requests)";
  if (access.tokens_required && token_store.empty()) return "token_store: needed when tokens are required";
  return "";
}

HttpServer::HttpServer(service::ServiceApi& service, HttpServerOptions options)
    : service_(service),
      options_(std::move(options)),
      sessions_(options_.logins_file, RealtimeNowNs()),
      queue_(kMaxQueuedFrames) {
  if (const std::string error = options_.Check(); !error.empty()) throw std::invalid_argument("HTTP API: " + error);
  if (options_.access.tokens_required) tokens_ = std::make_unique<TokenVerifier>(options_.token_store);
  const HostPort address = ParseHostPort(options_.listen);
  const std::string ports = (address.host.empty() || address.host == "*" ? std::string("0.0.0.0") : address.host) +
                            ":" + std::to_string(address.port);
  const std::string threads = std::to_string(options_.threads);
  const std::string timeout = std::to_string(options_.request_timeout_ms);
  mg_init_library(0);
  // Keep-alive stays off (civetweb's default): every answer closes its connection, so an idle
  // client holds a worker only until request_timeout_ms. The accept queue is as long as the workers.
  const char* civet_options[] = {"listening_ports", ports.c_str(), "num_threads", threads.c_str(),
                                 "request_timeout_ms", timeout.c_str(), "connection_queue", threads.c_str(),
                                 "listen_backlog", threads.c_str(), "enable_websocket_ping_pong", "yes",
                                 // A WebSocket is pinged after this long without a message from
                                 // its client (and closed when pings go unanswered).
                                 "websocket_timeout_ms", "10000", nullptr};
  mg_callbacks callbacks;
  std::memset(&callbacks, 0, sizeof(callbacks));
  // Requests are answered after the frame at hand: civetweb's threads run below the frame loop.
  callbacks.init_thread = [](const mg_context*, int) -> void* {
    SetThisThreadPriority(ThreadPriority::kService);
    return nullptr;
  };
  context_ = mg_start(&callbacks, this, civet_options);
  if (!context_) throw std::runtime_error("HTTP API: cannot listen on " + ports + " (in use, or not an address of this host)");
  mg_server_port bound[4];
  const int n = mg_get_server_ports(context_, 4, bound);
  if (n > 0) port_ = static_cast<uint16_t>(bound[0].port);
  // civetweb tries exact and "/api/..." prefix handlers before patterns: "**" is everything else.
  mg_set_request_handler(context_, "/api", RequestTrampoline, nullptr);
  mg_set_request_handler(context_, "**", StaticTrampoline, nullptr);
  for (const char* path : {"/api/live", "/api/stream"})
    mg_set_websocket_handler(context_, path, WebSocketConnect, WebSocketReady, WebSocketData, WebSocketClose, nullptr);
  broadcaster_ = std::thread([this] {
    SetThisThreadPriority(ThreadPriority::kService);
    Broadcast();
  });
}

HttpServer::~HttpServer() {
  stopping_ = true;
  queue_.Close();
  broadcaster_.join();
  // Closing the connections ends their writers (OnWebSocketClose joins each).
  mg_stop(context_);
  mg_exit_library();
}

AccessDecision HttpServer::Decide(const mg_connection* connection, bool websocket) {
  const mg_request_info* info = mg_get_request_info(connection);
  AccessRequest request;
  request.method = info->request_method ? info->request_method : "";
  request.path = info->local_uri ? info->local_uri : "";
  request.websocket = websocket;
  request.host = Header(connection, "Host");
  request.origin = Header(connection, "Origin");
  request.content_type = Header(connection, "Content-Type");
  request.custom = Header(connection, "X-Mocap-Request");
  request.sec_fetch_site = Header(connection, "Sec-Fetch-Site");
  request.authorization = Header(connection, "Authorization");
  request.cookie = Header(connection, "Cookie");
  const uint64_t now = RealtimeNowNs();
  return DecideAccess(
      request, options_.access,
      [&](const std::string& token) { return tokens_ ? tokens_->Verify(token, now) : std::nullopt; }, sessions_,
      now);
}

bool HttpServer::AnswerSession(mg_connection* connection, const std::string& path, const std::string& body,
                               const AccessDecision& access, int* status) {
  const std::string method = mg_get_request_info(connection)->request_method;
  std::string cookie;
  nlohmann::json answer;
  if (path == "/api/login") {
    if (method != "POST") return WriteError(connection, *status = 405, "log in with POST {\"token\": TOKEN}"), true;
    const nlohmann::json request = nlohmann::json::parse(body, nullptr, false);
    const std::string token = request.is_object() && request.contains("token") && request["token"].is_string()
                                  ? request["token"].get<std::string>()
                                  : "";
    std::optional<ApiPrincipal> who;
    if (!options_.access.tokens_required) who = ApiPrincipal{"anyone", ApiRole::kOperator};
    else if (!token.empty()) who = tokens_->Verify(token, RealtimeNowNs());
    if (!who) return WriteError(connection, *status = 401, "the token is not valid"), true;
    cookie = std::string("Set-Cookie: ") + kSessionCookie + "=" + sessions_.Create(*who, RealtimeNowNs()) +
             "; Path=/; HttpOnly; SameSite=Strict; Max-Age=43200\r\n";
    answer = {{"name", who->name}, {"role", RoleName(who->role)}};
  } else if (path == "/api/logout") {
    if (method != "POST") return WriteError(connection, *status = 405, "log out with POST"), true;
    sessions_.Remove(CookieValue(Header(connection, "Cookie"), kSessionCookie));
    cookie = std::string("Set-Cookie: ") + kSessionCookie + "=; Path=/; HttpOnly; SameSite=Strict; Max-Age=0\r\n";
    answer = {{"logged_out", true}};
  } else if (path == "/api/whoami") {
    answer = {{"name", access.who.name},
              {"role", RoleName(access.who.role)},
              {"tokens_required", options_.access.tokens_required}};
  } else {
    return false;
  }
  const std::string text = answer.dump();
  WriteHead(connection, "HTTP/1.1 200 OK\r\nContent-Type: application/json\r\nContent-Length: " +
                            std::to_string(text.size()) + "\r\nCache-Control: no-store\r\n" + cookie +
                            "Connection: close\r\n\r\n" + text);
  *status = 200;
  return true;
}

int HttpServer::OnRequest(mg_connection* connection) {
  const mg_request_info* info = mg_get_request_info(connection);
  ApiRequest request;
  request.method = info->request_method ? info->request_method : "";
  request.path = info->local_uri ? info->local_uri : "";
  request.query = info->query_string ? info->query_string : "";
  const AccessDecision access = Decide(connection, false);
  if (access.status) {
    WriteError(connection, access.status, access.reason,
               access.status == 401 ? "WWW-Authenticate: Bearer realm=\"mocap-hub\"\r\n" : "");
    return access.status;
  }
  ApiResponse response;
  if (request.path == "/api/live" || request.path == "/api/stream") {
    response.status = 400;
    response.body = "{\"error\":\"" + request.path + " is a WebSocket: connect with an Upgrade request\"}";
  } else if (info->content_length > static_cast<long long>(kMaxApiBody)) {
    response.status = 413;
    response.body = R"({"error":"the body is larger than 64 KiB"})";
  } else {
    // Read at most the limit plus one byte, so a lying Content-Length cannot make us buffer more,
    // and for at most one request timeout: a body that trickles in (or never comes) does not
    // hold the worker longer.
    std::vector<char> buffer(kMaxApiBody + 1);
    size_t got = 0;
    int r;
    const uint64_t deadline = RealtimeNowNs() + static_cast<uint64_t>(options_.request_timeout_ms) * 1'000'000;
    const size_t expected = info->content_length >= 0 ? static_cast<size_t>(info->content_length) : buffer.size();
    while (got < std::min(expected, buffer.size()) && RealtimeNowNs() < deadline &&
           (r = mg_read(connection, buffer.data() + got, std::min(expected, buffer.size()) - got)) > 0)
      got += static_cast<size_t>(r);
    if (info->content_length > 0 && got < expected) {
      WriteError(connection, 408, "the body did not arrive within " + std::to_string(options_.request_timeout_ms) + " ms");
      return 408;
    }
    request.body.assign(buffer.data(), got);
    int status = 0;
    if (AnswerSession(connection, request.path, request.body, access, &status)) return status;
    response = HandleApiRequest(service_, request);
  }
  if (response.status == 200 && !response.file.empty())
    return SendFile(connection, response.file, response.content_type, request.method == "HEAD", "");
  WriteHead(connection, "HTTP/1.1 " + std::to_string(response.status) + " " + Reason(response.status) +
                            "\r\nContent-Type: " + response.content_type + "\r\nContent-Length: " +
                            std::to_string(response.body.size()) + "\r\nCache-Control: no-store\r\nConnection: close\r\n\r\n");
  mg_write(connection, response.body.data(), response.body.size());
  return response.status;
}

int HttpServer::OnStaticRequest(mg_connection* connection) {
  const mg_request_info* info = mg_get_request_info(connection);
  const std::string method = info->request_method ? info->request_method : "";
  const std::string path = info->local_uri ? info->local_uri : "";
  int status = 0;
  std::string body;
  StaticFile file;
  if (const std::string why = CheckHost(Header(connection, "Host"), options_.access); !why.empty()) {
    WriteError(connection, 421, why);
    return 421;
  }
  if (method != "GET" && method != "HEAD") {
    status = 405;
    body = R"({"error":"the console's files are read with GET"})";
  } else {
    file = ResolveStaticFile(options_.console, path);
    if (file.status != 200) {
      status = file.status;
      body = options_.console.empty() ? "{\"error\":\"this serve has no web console (--web-root)\"}"
                              : nlohmann::json{{"error", file.reason}}.dump(-1, ' ', false,
                                                                           nlohmann::json::error_handler_t::replace);
    }
  }
  if (status) {
    WriteHead(connection, "HTTP/1.1 " + std::to_string(status) + " " + Reason(status) +
                              "\r\nContent-Type: application/json\r\nContent-Length: " + std::to_string(body.size()) +
                              "\r\nConnection: close\r\n\r\n");
    mg_write(connection, body.data(), body.size());
    return status;
  }
  // The file's size and time as its version: a browser revalidates (no-cache) and gets a 304.
  struct stat st;
  char etag[64] = "";
  if (::stat(file.path.c_str(), &st) == 0)
    std::snprintf(etag, sizeof etag, "\"%llx-%llx\"", static_cast<unsigned long long>(st.st_size),
                  static_cast<unsigned long long>(st.st_mtim.tv_sec) * 1000000000ull +
                      static_cast<unsigned long long>(st.st_mtim.tv_nsec));
  const char* if_none_match = mg_get_header(connection, "If-None-Match");
  if (etag[0] && if_none_match && std::strcmp(if_none_match, etag) == 0) {
    WriteHead(connection, std::string("HTTP/1.1 304 Not Modified\r\nETag: ") + etag +
                              "\r\nCache-Control: no-cache\r\nContent-Length: 0\r\nConnection: close\r\n\r\n");
    return 304;
  }
  const std::string headers =
      std::string("Cache-Control: no-cache\r\n") + (etag[0] ? "ETag: " + std::string(etag) + "\r\n" : "");
  return SendFile(connection, file.path, file.content_type, method == "HEAD", headers);
}

int HttpServer::AcceptWebSocket(const mg_connection* connection) {
  // civetweb closes a refused upgrade without a word; the answer written here says why.
  mg_connection* writable = const_cast<mg_connection*>(connection);
  const AccessDecision access = Decide(connection, true);
  if (access.status) {
    WriteError(writable, access.status, access.reason);
    return access.status;
  }
  std::lock_guard<std::mutex> lock(clients_mutex_);
  // Counted with the ones whose upgrade is under way, so that a burst cannot pass the cap.
  if (clients_.size() + upgrading_ >= options_.max_websockets) {
    WriteError(writable, 503,
               std::to_string(options_.max_websockets) + " WebSocket clients already (the limit, so that requests "
               "keep their workers); close one and connect again");
    return 503;
  }
  ++upgrading_;
  return 0;
}

void HttpServer::OnWebSocketReady(mg_connection* connection) {
  auto client = std::make_unique<Client>();
  client->connection = connection;
  client->binary = IsStream(connection);
  client->parts = client->binary ? PartsOf(connection) : 0;
  if (!client->binary) {
    const int max_fps = LiveQueryOf(connection).value_or(LiveQuery{}).max_fps;
    if (max_fps) client->min_interval = std::chrono::nanoseconds(1'000'000'000 / max_fps);
  }
  client->writer = std::thread(Write, client.get());
  std::lock_guard<std::mutex> lock(clients_mutex_);
  if (upgrading_ > 0) --upgrading_;
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
  SetThisThreadPriority(ThreadPriority::kService);
  while (!client->queue.closed()) {
    const stream::SharedFrame frame = client->queue.Pop(std::chrono::seconds(1));
    if (!frame) continue;
    if (client->min_interval.count()) {
      // At most max_fps frames per second on average: a frame is sent when its slot is due; a
      // late frame may use the slot it missed (at most one), so 100 Hz thinned to 60 gives 60.
      const auto now = std::chrono::steady_clock::now();
      if (now < client->next_due) continue;
      client->next_due = std::max(client->next_due, now - client->min_interval) + client->min_interval;
    }
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
