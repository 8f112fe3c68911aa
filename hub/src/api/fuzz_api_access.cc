// libFuzzer target: arbitrary header values through the access rules (access.h) and arbitrary
// token stores through their parser. The input is split at NUL bytes into the request's fields;
// nothing may crash or throw, a refusal always has a reason and a status of 401, 403 or 421,
// and nothing without a token or a login is let in when tokens are required.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include "api/access.h"
#include "api/api_tokens.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  std::vector<std::string> parts;
  size_t start = 0;
  for (size_t i = 0; i <= input.size(); ++i) {
    if (i == input.size() || input[i] == '\0') {
      parts.push_back(input.substr(start, i - start));
      start = i + 1;
    }
  }
  parts.resize(10);
  mocap::api::AccessRequest request;
  request.method = parts[0];
  request.path = parts[1];
  request.websocket = !parts[2].empty() && parts[2][0] == 'w';
  request.host = parts[3];
  request.origin = parts[4];
  request.content_type = parts[5];
  request.custom = parts[6];
  request.sec_fetch_site = parts[7];
  request.authorization = parts[8];
  request.cookie = parts[9];
  static mocap::api::LoginSessions sessions;
  const mocap::api::AccessOptions options;
  bool token_accepted = false;
  const mocap::api::AccessDecision decision = mocap::api::DecideAccess(
      request, options,
      [&](const std::string& token) -> std::optional<mocap::api::ApiPrincipal> {
        if (token != "good") return std::nullopt;
        token_accepted = true;
        return mocap::api::ApiPrincipal{"fuzz", mocap::api::ApiRole::kViewer};
      },
      sessions, 1);
  if (decision.status != 0 && decision.status != 401 && decision.status != 403 && decision.status != 421) std::abort();
  if (decision.status != 0 && decision.reason.empty()) std::abort();
  if (decision.status == 0 && request.path != "/api/login" && !token_accepted) std::abort();
  try {
    const auto entries = mocap::api::ParseTokenStore(input, "fuzz");
    if (mocap::api::ParseTokenStore(mocap::api::FormatTokenStore(entries), "again").size() != entries.size())
      std::abort();
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
