// libFuzzer target: arbitrary bytes as an edit log (JSON parse, then every operation's checks);
// a log that is accepted must write back to JSON that reads to the same log, and applying it to a
// small take must either work or be refused with std::invalid_argument.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "edit/edit_apply.h"
#include "edit/edit_log.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const mocap::edit::EditLog log = mocap::edit::ParseEditLog(text, "fuzz");
    const nlohmann::json written = mocap::edit::EditLogToJson(log);
    if (mocap::edit::EditLogToJson(mocap::edit::EditLogFromJson(written, "fuzz")) != written) std::abort();
    mocap::MarkerTrajectories m;
    m.rate_hz = 100.0;
    m.names = {"A", "B", "C", "D"};
    for (uint64_t f = 0; f < 40; ++f) {
      const size_t i = m.AddFrame(f);
      for (size_t c = 0; c < 4; ++c)
        if ((f * 7 + c * 3) % 11 != 0) m.At(i, c) = Eigen::Vector3d(static_cast<double>(c) * 100.0, f * 1.0 + c, f * 0.5 * c);
    }
    mocap::edit::EditedTake take = mocap::edit::EditedTake::FromMeasured(std::move(m));
    mocap::edit::ApplyEdits(log, &take);
    if (take.marks.size() != take.markers.points.size()) std::abort();
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
