// Keeping the calibrations an apply replaces (see calibration_files.h).
#include "service/calibration_files.h"

#include <ctime>
#include <filesystem>
#include <system_error>

#include "service/api_error.h"
#include "util/json_file.h"

namespace mocap::service {

std::string DatedCopyName(const std::string& path, uint64_t now_ns) {
  const std::time_t seconds = static_cast<std::time_t>(now_ns / 1'000'000'000);
  std::tm utc{};
  gmtime_r(&seconds, &utc);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y-%m-%dT%H%M%SZ", &utc);
  std::string name = path + "." + stamp;
  for (int n = 2; std::filesystem::exists(name); ++n) name = path + "." + stamp + "-" + std::to_string(n);
  return name;
}

void ReplaceCalibrationKeepingOld(const std::string& path, const nlohmann::json& document, uint64_t now_ns) {
  const std::string kept = DatedCopyName(path, now_ns);
  std::error_code ec;
  std::filesystem::copy_file(path, kept, std::filesystem::copy_options::none, ec);
  if (ec) throw ApiError(500, kept + ": cannot keep the old calibration: " + ec.message());
  try {
    WriteJsonFile(document, path);
  } catch (const std::exception& e) {
    throw ApiError(500, e.what());
  }
}

}  // namespace mocap::service
