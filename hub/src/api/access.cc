// Who may make this request (see access.h).
#include "api/access.h"

#include <arpa/inet.h>

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "util/log.h"

namespace mocap::api {
namespace {

std::string Lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

std::string Trim(const std::string& text) {
  const size_t begin = text.find_first_not_of(" \t");
  if (begin == std::string::npos) return "";
  return text.substr(begin, text.find_last_not_of(" \t") - begin + 1);
}

// Host without its port: "[::1]:80" -> "::1", "a.b:80" -> "a.b"; "" when malformed.
std::string HostName(const std::string& host) {
  if (!host.empty() && host[0] == '[') {
    const size_t close = host.find(']');
    if (close == std::string::npos) return "";
    const std::string rest = host.substr(close + 1);
    if (!rest.empty() && (rest[0] != ':' || rest.size() == 1)) return "";
    return host.substr(1, close - 1);
  }
  const size_t colon = host.find(':');
  if (colon == std::string::npos) return host;
  if (host.find(':', colon + 1) != std::string::npos || colon + 1 == host.size()) return "";
  for (size_t i = colon + 1; i < host.size(); ++i)
    if (!std::isdigit(static_cast<unsigned char>(host[i]))) return "";
  return host.substr(0, colon);
}

std::string IdKey(const std::string& id) {
  const TokenHash hash = HashToken(id);
  static const char* hex = "0123456789abcdef";
  std::string out;
  for (const uint8_t b : hash) {
    out += hex[b >> 4];
    out += hex[b & 15];
  }
  return out;
}

bool IsIpLiteral(const std::string& name) {
  unsigned char buffer[16];
  return inet_pton(AF_INET, name.c_str(), buffer) == 1 || inet_pton(AF_INET6, name.c_str(), buffer) == 1;
}

}  // namespace

LoginSessions::LoginSessions(std::string file, uint64_t now_ns) : file_(std::move(file)) {
  if (file_.empty()) return;
  std::ifstream in(file_);
  if (!in) return;
  try {
    const nlohmann::json document = nlohmann::json::parse(in);
    for (const auto& item : document.at("sessions")) {
      const std::optional<ApiRole> role = ParseRole(item.at("role").get<std::string>());
      const std::string key = item.at("id_hash").get<std::string>();
      if (!role || key.size() != 64 || sessions_.size() >= kMaxSessions) continue;
      sessions_[key] = Entry{{item.at("name").get<std::string>(), *role}, now_ns};
    }
  } catch (const std::exception& e) {
    log::Warn("{}: logins not restored ({}); the browsers log in again", file_, e.what());
    sessions_.clear();
  }
}

void LoginSessions::Save() {
  if (file_.empty()) return;
  nlohmann::json list = nlohmann::json::array();
  for (const auto& [key, entry] : sessions_)
    list.push_back({{"id_hash", key}, {"name", entry.who.name}, {"role", RoleName(entry.who.role)}});
  const std::string tmp = file_ + ".tmp";
  {
    std::ofstream out(tmp, std::ios::trunc);
    ::chmod(tmp.c_str(), 0600);
    out << nlohmann::json{{"sessions", list}}.dump() << "\n";
    if (!out.flush()) {
      log::Warn("{}: cannot keep the logins", tmp);
      return;
    }
  }
  if (std::rename(tmp.c_str(), file_.c_str()) != 0) log::Warn("{}: cannot keep the logins", file_);
}

std::string LoginSessions::Create(const ApiPrincipal& who, uint64_t now_ns) {
  const std::string id = GenerateToken();
  std::lock_guard<std::mutex> lock(mutex_);
  for (auto it = sessions_.begin(); it != sessions_.end();)
    it = now_ns > it->second.last_used_ns + kIdleNs ? sessions_.erase(it) : std::next(it);
  if (sessions_.size() >= kMaxSessions) {
    const auto oldest = std::min_element(sessions_.begin(), sessions_.end(), [](const auto& a, const auto& b) {
      return a.second.last_used_ns < b.second.last_used_ns;
    });
    sessions_.erase(oldest);
  }
  sessions_[IdKey(id)] = Entry{who, now_ns};
  Save();
  return id;
}

std::optional<ApiPrincipal> LoginSessions::Find(const std::string& id, uint64_t now_ns) {
  const std::string key = IdKey(id);
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = sessions_.find(key);
  if (it == sessions_.end()) return std::nullopt;
  if (now_ns > it->second.last_used_ns + kIdleNs) {
    sessions_.erase(it);
    return std::nullopt;
  }
  it->second.last_used_ns = std::max(it->second.last_used_ns, now_ns);
  return it->second.who;
}

void LoginSessions::Remove(const std::string& id) {
  const std::string key = IdKey(id);
  std::lock_guard<std::mutex> lock(mutex_);
  if (sessions_.erase(key)) Save();
}

bool IsStateChange(const std::string& method) { return method != "GET" && method != "HEAD"; }

std::string CheckHost(const std::string& host, const AccessOptions& options) {
  const std::string name = Lower(HostName(Trim(host)));
  if (name.empty()) return "Host '" + host + "': a Host header naming this hub is required";
  if (name == "localhost" || IsIpLiteral(name)) return "";
  for (const std::string& allowed : options.host_names)
    if (Lower(allowed) == name) return "";
  return "Host '" + host + "' is not an address of this hub (IP addresses, localhost and --api-host-name are)";
}

std::string CheckOrigin(const AccessRequest& request) {
  const std::string origin = Lower(Trim(request.origin));
  if (origin.empty()) return "";
  const std::string host = Lower(Trim(request.host));
  if (origin == "http://" + host || origin == "https://" + host) return "";
  if (!request.websocket && !IsStateChange(request.method)) return "";
  return "Origin '" + request.origin + "' is not this hub: a page elsewhere may not steer it";
}

std::string CheckCsrf(const AccessRequest& request) {
  if (!IsStateChange(request.method)) return "";
  const std::string site = Lower(Trim(request.sec_fetch_site));
  if (!site.empty() && site != "same-origin" && site != "none")
    return "Sec-Fetch-Site '" + request.sec_fetch_site + "': state changes come from this hub's own pages";
  const std::string type = Lower(Trim(request.content_type));
  const bool json = type.rfind("application/json", 0) == 0 &&
                    (type.size() == 16 || type[16] == ';' || type[16] == ' ');
  if (json || Trim(request.custom) == "1") return "";
  return "a state change must be sent as Content-Type: application/json (or with X-Mocap-Request: 1)";
}

std::string BearerToken(const std::string& authorization) {
  const std::string text = Trim(authorization);
  if (text.size() < 7 || Lower(text.substr(0, 7)) != "bearer ") return "";
  return Trim(text.substr(7));
}

std::string CookieValue(const std::string& cookie, const std::string& name) {
  size_t pos = 0;
  while (pos < cookie.size()) {
    size_t end = cookie.find(';', pos);
    if (end == std::string::npos) end = cookie.size();
    const std::string pair = Trim(cookie.substr(pos, end - pos));
    const size_t eq = pair.find('=');
    if (eq != std::string::npos && pair.substr(0, eq) == name) return pair.substr(eq + 1);
    pos = end + 1;
  }
  return "";
}

AccessDecision DecideAccess(const AccessRequest& request, const AccessOptions& options, const TokenCheck& tokens,
                            LoginSessions& sessions, uint64_t now_ns) {
  AccessDecision decision;
  if (std::string why = CheckHost(request.host, options); !why.empty()) return {421, why, {}};
  if (std::string why = CheckOrigin(request); !why.empty()) return {403, why, {}};
  if (std::string why = CheckCsrf(request); !why.empty()) return {403, why, {}};
  if (request.path == "/api/login") return decision;
  if (!options.tokens_required) {
    decision.who = {"anyone", ApiRole::kOperator};
    return decision;
  }
  std::optional<ApiPrincipal> who;
  const std::string token = BearerToken(request.authorization);
  if (!token.empty()) {
    who = tokens(token);
    if (!who) return {401, "the token is not valid (revoked, rotated or mistyped)", {}};
  } else if (const std::string id = CookieValue(request.cookie, kSessionCookie); !id.empty()) {
    who = sessions.Find(id, now_ns);
    if (!who) return {401, "the login has expired: log in again", {}};
  } else {
    return {401, "log in: a token is needed (Authorization: Bearer TOKEN, or the console's login)", {}};
  }
  decision.who = *who;
  if (IsStateChange(request.method) && request.path != "/api/logout" && who->role != ApiRole::kOperator)
    return {403, "'" + who->name + "' is a viewer: only operators may change anything", *who};
  return decision;
}

}  // namespace mocap::api
