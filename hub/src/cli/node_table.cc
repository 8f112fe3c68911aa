// The node table (see node_table.h).
#include "cli/node_table.h"

#include <fmt/format.h>

namespace mocap {
using nlohmann::json;

std::string JsonFieldText(const json& j, const char* key) {
  if (!j.contains(key) || j[key].is_null()) return "-";
  return j[key].is_string() ? j[key].get<std::string>() : j[key].dump();
}

std::string NodeTableHeader() {
  return fmt::format("{:>4}  {:<21}  {:<12}  {:<10}  {:>6}  {:>8}  {:>9}  {:>9}  {:>5}  {:>6}  {:>9}  {}", "id", "address",
                     "state", "firmware", "fps", "detect", "sent", "dropped", "thr", "temp", "jitter", "seen");
}

std::string NodeTableRow(const json& n) {
  const std::string temp = n["temperature_c"].is_null() ? "-" : fmt::format("{:.1f}", n["temperature_c"].get<double>());
  // A camera whose image size is not the calibration's (image_size_check.h) is flagged here.
  std::string image;
  const std::string size = JsonFieldText(n, "width") + "x" + JsonFieldText(n, "height");
  if (n.value("rescaled_frames", 0ull) > 0)
    image += ", " + size + " images rescaled to the calibration's (" + JsonFieldText(n, "rescaled_frames") + " frames)";
  if (n.value("wrong_size_frames", 0ull) > 0)
    image += ", " + size + " images REFUSED: not the calibration's size (" + JsonFieldText(n, "wrong_size_frames") + " frames)";
  // Before its first frame a node has no rate, detection time or frames sent: zeros there read as
  // a fault, so those columns say what it waits for.
  const unsigned long long sent = n["frames_sent"].get<unsigned long long>();
  const std::string rates = sent == 0 && n["state"].get<std::string>() == "running"
                                ? fmt::format("{:<27}", "waiting for the first trigger")
                                : fmt::format("{:>6.1f}  {:>6}us  {:>9}", n["fps"].get<double>(),
                                              n["detect_us_mean"].get<unsigned>(), sent);
  return fmt::format("{:>4}  {:<21}  {:<12}  {:<10}  {}  {:>9}  {:>5}  {:>6}  {:>7}ns  {:.1f}s ago{}{}",
                     n["id"].get<unsigned>(), n["address"].get<std::string>(), n["state"].get<std::string>(),
                     n["firmware"].get<std::string>(), rates, n["frames_dropped"].get<unsigned long long>(),
                     n["threshold"].get<unsigned>(), temp, n["sync"]["edge_jitter_ns"].get<unsigned>(),
                     n["last_seen_s"].get<double>(), n["masked"].get<bool>() ? ", masked" : "", image);
}

}  // namespace mocap
