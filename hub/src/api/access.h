// Who may make this request, decided from its method, path and headers alone (no sockets: unit
// tested and fuzzed by fuzz_api_access). The rules, in order, for every API request and WebSocket:
//   Host   an IP address literal, "localhost" or a name given to serve (--api-host-name): a
//          page on another name that resolves here (DNS rebinding) is refused, 421.
//   Origin absent (not a browser) or this very host (http:// or https:// + Host); a WebSocket or
//          state change from any other page is refused, 403.
//   CSRF   a state change (any method but GET and HEAD) carries Content-Type application/json or
//          X-Mocap-Request: 1 (a cross-origin page can send neither without a CORS preflight,
//          which serve never grants) and no Sec-Fetch-Site other than same-origin or none, 403.
//   Who    a token (Authorization: Bearer T) or a console login's session cookie; else 401.
//   Role   viewers read (GET, HEAD, the WebSockets); anything else needs an operator, 403.
// Logins: POST /api/login {"token": T} gives a session id for the cookie (HttpOnly,
// SameSite=Strict), idle for at most 12 hours, at most 256 at once (the oldest goes). They are
// kept (as BLAKE2b hashes of their ids, mode 0600) in a file beside the tokens, so that a
// restarted serve still knows its browsers; revoking a token does not end the logins made with
// it (log out, or remove the file).
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "api/api_tokens.h"

namespace mocap::api {

struct AccessOptions {
  // false: serve --api-auth off (loopback) or --insecure-dev-api: everyone is an operator; the
  // Host, Origin and CSRF rules still hold.
  bool tokens_required = true;
  std::vector<std::string> host_names;  // names besides IP literals and localhost
};

struct AccessRequest {
  std::string method;
  std::string path;
  bool websocket = false;
  std::string host;            // the Host header
  std::string origin;          // Origin
  std::string content_type;    // Content-Type
  std::string custom;          // X-Mocap-Request
  std::string sec_fetch_site;  // Sec-Fetch-Site
  std::string authorization;   // Authorization
  std::string cookie;          // Cookie
};

struct AccessDecision {
  int status = 0;  // 0: allowed; else 401, 403 or 421
  std::string reason;
  ApiPrincipal who;
};

inline constexpr const char* kSessionCookie = "mocap_session";

// The console's login sessions (ids of 32 random bytes as hex). Thread-safe.
class LoginSessions {
 public:
  static constexpr size_t kMaxSessions = 256;
  static constexpr uint64_t kIdleNs = 12ull * 3600 * 1'000'000'000;

  // file: where they are kept across restarts ("" keeps them in memory only); an unreadable
  // file is started afresh (the browsers log in again), said in the log.
  explicit LoginSessions(std::string file = "", uint64_t now_ns = 0);

  std::string Create(const ApiPrincipal& who, uint64_t now_ns);
  std::optional<ApiPrincipal> Find(const std::string& id, uint64_t now_ns);
  void Remove(const std::string& id);

 private:
  struct Entry {
    ApiPrincipal who;
    uint64_t last_used_ns = 0;
  };
  void Save();  // under mutex_

  std::string file_;
  std::mutex mutex_;
  std::map<std::string, Entry> sessions_;  // by the hash of the id
};

using TokenCheck = std::function<std::optional<ApiPrincipal>(const std::string& token)>;

// The Host, Origin and CSRF rules (the first three above): "" or the refusal.
std::string CheckHost(const std::string& host, const AccessOptions& options);
std::string CheckOrigin(const AccessRequest& request);
std::string CheckCsrf(const AccessRequest& request);
bool IsStateChange(const std::string& method);
// The token of "Bearer T" ("" when the header is another scheme or empty).
std::string BearerToken(const std::string& authorization);
// One cookie's value in a Cookie header ("" when absent).
std::string CookieValue(const std::string& cookie, const std::string& name);

// Every rule above. `tokens` checks a bearer token; `sessions` a login cookie. /api/login
// passes without credentials (it is how a browser gets them); the rules before it still hold.
AccessDecision DecideAccess(const AccessRequest& request, const AccessOptions& options, const TokenCheck& tokens,
                            LoginSessions& sessions, uint64_t now_ns);

}  // namespace mocap::api
