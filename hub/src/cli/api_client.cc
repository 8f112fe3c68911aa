// HTTP client of serve's API (see api_client.h).
#include "cli/api_client.h"

#include <civetweb.h>

#include <unistd.h>

#include <cstdlib>
#include <stdexcept>

#include "api/api_tokens.h"
#include "ingest/udp_socket.h"

namespace mocap {
namespace {

constexpr int kAnswerTimeoutMs = 30000;  // the longest request (an automatic mask) answers in seconds
constexpr size_t kMaxAnswer = 64u << 20;

constexpr const char* kInstalledTokenFile = "/var/lib/mocap-hub/api-auth/operator.token";

std::string& TokenFileOption() {
  static std::string file;
  return file;
}

// Where this user keeps a token of their own: $XDG_CONFIG_HOME/mocap-hub/token, else
// ~/.config/mocap-hub/token ("" without a home).
std::string UserTokenFile() {
  if (const char* config = std::getenv("XDG_CONFIG_HOME"); config && *config == '/')
    return std::string(config) + "/mocap-hub/token";
  if (const char* home = std::getenv("HOME"); home && *home) return std::string(home) + "/.config/mocap-hub/token";
  return "";
}

// Where the token in use came from, for the hint on a refusal ("" when there was none).
std::string& TokenSource() {
  static std::string source;
  return source;
}

struct Connection {
  mg_connection* c = nullptr;
  ~Connection() {
    if (c) mg_close_connection(c);
  }
};

}  // namespace

ApiAnswer CallApi(const std::string& address, const std::string& method, const std::string& path,
                  const std::string& body) {
  const HostPort hp = ParseHostPort(address);
  const std::string host = hp.host.empty() || hp.host == "*" ? "127.0.0.1" : hp.host;
  char error[256] = "";
  mg_init_library(0);
  Connection connection;
  connection.c = mg_connect_client(host.c_str(), hp.port, 0, error, sizeof(error));
  if (!connection.c)
    throw std::runtime_error("cannot reach mocap-hub serve at " + host + ":" + std::to_string(hp.port) + " (" +
                             error + "); is it running? (--api or MOCAP_HUB_API give its address)");
  const std::string token = ApiToken();
  const std::string authorization = token.empty() ? "" : "Authorization: Bearer " + token + "\r\n";
  const std::string host_header = host.find(':') != std::string::npos ? "[" + host + "]" : host;
  mg_printf(connection.c,
            "%s %s HTTP/1.1\r\nHost: %s:%u\r\nContent-Type: application/json\r\nContent-Length: %zu\r\n"
            "%sConnection: close\r\n\r\n",
            method.c_str(), path.c_str(), host_header.c_str(), static_cast<unsigned>(hp.port), body.size(),
            authorization.c_str());
  if (!body.empty()) mg_write(connection.c, body.data(), body.size());
  if (mg_get_response(connection.c, error, sizeof(error), kAnswerTimeoutMs) < 0)
    throw std::runtime_error("mocap-hub serve at " + address + " gave no answer: " + error);
  const mg_response_info* info = mg_get_response_info(connection.c);
  ApiAnswer answer;
  answer.status = info->status_code;
  for (int i = 0; i < info->num_headers; ++i)
    if (strcasecmp(info->http_headers[i].name, "Content-Type") == 0) answer.content_type = info->http_headers[i].value;
  char buffer[16384];
  int got;
  while ((got = mg_read(connection.c, buffer, sizeof(buffer))) > 0) {
    if (answer.body.size() + static_cast<size_t>(got) > kMaxAnswer)
      throw std::runtime_error("mocap-hub serve's answer is larger than 64 MiB");
    answer.body.append(buffer, static_cast<size_t>(got));
  }
  return answer;
}

nlohmann::json CallApiJson(const std::string& address, const std::string& method, const std::string& path,
                           const nlohmann::json& body) {
  const ApiAnswer answer = CallApi(address, method, path, body.is_null() ? "" : body.dump());
  nlohmann::json document = nlohmann::json::parse(answer.body, nullptr, false);
  if (answer.status < 200 || answer.status >= 300) {
    const std::string reason = document.is_object() && document.contains("error") && document["error"].is_string()
                                   ? document["error"].get<std::string>()
                                   : answer.body.substr(0, 200);
    std::string hint;
    if (answer.status == 401 && ApiToken().empty())
      hint = "; no API token found (docs/security.md): on the hub run it as root (sudo) to use the installed "
             "service's " + std::string(kInstalledTokenFile) + ", or have one issued to you: sudo mocap-hub tokens new "
             "$USER --role operator --dir /var/lib/mocap-hub/api-auth --out " + UserTokenFile() +
             "; or set MOCAP_HUB_TOKEN_FILE / --token-file (serve writes api-auth/operator.token beside its sessions "
             "directory)";
    else if (answer.status == 401)
      hint = "; the token from " + TokenSource() + " was refused (revoked or rotated? `mocap-hub tokens`)";
    throw std::runtime_error(reason + " (HTTP " + std::to_string(answer.status) + ")" + hint);
  }
  if (document.is_discarded()) throw std::runtime_error("mocap-hub serve answered with something that is not JSON");
  return document;
}

void AddApiOption(CLI::App& command, std::string* address) {
  const char* env = std::getenv("MOCAP_HUB_API");
  *address = env && *env ? env : kDefaultApiAddress;
  command.add_option("--api", *address, "HOST:PORT of mocap-hub serve's API (default $MOCAP_HUB_API or 127.0.0.1:7801)");
  command.add_option("--token-file", TokenFileOption(),
                     "The API token's file (default $MOCAP_HUB_TOKEN_FILE, else the first readable of "
                     "./api-auth/operator.token, ~/.config/mocap-hub/token, " +
                         std::string(kInstalledTokenFile) + ")");
}

std::string ApiToken() {
  static const std::string token = [] {
    if (const char* env = std::getenv("MOCAP_HUB_TOKEN"); env && *env) {
      TokenSource() = "$MOCAP_HUB_TOKEN";
      return std::string(env);
    }
    std::string file = TokenFileOption();
    if (file.empty())
      if (const char* env = std::getenv("MOCAP_HUB_TOKEN_FILE"); env && *env) file = env;
    if (!file.empty()) {
      TokenSource() = file;
      return api::ReadTokenFile(file);
    }
    // serve run here (its default api-auth beside ./sessions), this user's own token, the
    // installed service's local operator token (readable by root and the service's user).
    for (const std::string& candidate : {std::string("api-auth/operator.token"), UserTokenFile(),
                                         std::string(kInstalledTokenFile)})
      if (!candidate.empty() && ::access(candidate.c_str(), R_OK) == 0) {
        TokenSource() = candidate;
        return api::ReadTokenFile(candidate);
      }
    return std::string();
  }();
  return token;
}

}  // namespace mocap
