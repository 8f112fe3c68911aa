// The CLI's side of `serve`'s HTTP API (civetweb's client): one request, one answer. The address
// comes from --api, else $MOCAP_HUB_API, else 127.0.0.1:7801 (serve's default). Every request
// carries the API token (api/api_tokens.h) as "Authorization: Bearer": $MOCAP_HUB_TOKEN (the
// token itself), else the file --token-file or $MOCAP_HUB_TOKEN_FILE names, else the first of
// these files this user can read: ./api-auth/operator.token (serve run here with --sessions-dir
// sessions), the user's own $XDG_CONFIG_HOME/mocap-hub/token (~/.config/mocap-hub/token; issued
// by `sudo mocap-hub tokens new ... --out` it), /var/lib/mocap-hub/api-auth/operator.token (the
// installed service's, for root). One command per process: the token is looked up once.
#pragma once

#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

namespace mocap {

inline constexpr const char* kDefaultApiAddress = "127.0.0.1:7801";

struct ApiAnswer {
  int status = 0;
  std::string content_type;
  std::string body;
};

// Throws std::runtime_error when the service cannot be reached or answers malformed HTTP.
ApiAnswer CallApi(const std::string& address, const std::string& method, const std::string& path,
                  const std::string& body = "");
// The same for JSON answers: 2xx gives the document; any other status throws std::runtime_error
// with the service's reason.
nlohmann::json CallApiJson(const std::string& address, const std::string& method, const std::string& path,
                           const nlohmann::json& body = nullptr);

// --api HOST:PORT and --token-file FILE on a client command; *address starts as $MOCAP_HUB_API
// or the default.
void AddApiOption(CLI::App& command, std::string* address);

// The token the requests carry ("" when none was found: serve then answers 401); throws
// std::runtime_error when a named file cannot be read or holds no token.
std::string ApiToken();

}  // namespace mocap
