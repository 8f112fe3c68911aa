// Numeric option checks shared by the commands (see commands.h). CLI11's Range lets NaN through
// (every comparison with NaN is false), and a NaN duration or deadline would never end.
#include <cmath>
#include <cstdlib>
#include <string>

#include "cli/commands.h"

namespace mocap {

CLI::Validator FiniteRange(double lo, double hi) {
  const std::string range = "[" + CLI::detail::to_string(lo) + ", " + CLI::detail::to_string(hi) + "]";
  return CLI::Validator(
      [lo, hi, range](std::string& text) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v) || v < lo || v > hi)
          return "'" + text + "' is not a number within " + range;
        return {};
      },
      "NUMBER in " + range);
}

}  // namespace mocap
