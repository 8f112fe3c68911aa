// libFuzzer target: arbitrary API requests (method, path, query, body from the input) through
// the router over a fake service. Every request must get an answer with a status and, when it
// is an error, a JSON reason.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include <nlohmann/json.hpp>

#include "service/api_router.h"
#include "service/fake_service_api.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  // Fields separated by newlines: method, path, query, then the body (the rest).
  const std::string input(reinterpret_cast<const char*>(data), size);
  std::string fields[3];
  size_t pos = 0;
  for (std::string& field : fields) {
    const size_t end = input.find('\n', pos);
    field = input.substr(pos, end == std::string::npos ? std::string::npos : end - pos);
    pos = end == std::string::npos ? input.size() : end + 1;
  }
  mocap::service::FakeServiceApi api;
  const mocap::service::ApiResponse response =
      mocap::service::HandleApiRequest(api, {fields[0], fields[1], fields[2], input.substr(pos)});
  if (response.status < 200 || response.status > 599) std::abort();
  if (response.status >= 400 && !nlohmann::json::parse(response.body).contains("error")) std::abort();
  return 0;
}
