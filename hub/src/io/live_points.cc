// Live points files (see live_points.h).
#include "io/live_points.h"

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "util/bounded_line.h"

namespace mocap {
namespace {

constexpr const char* kMagic = "# mocap live points v1 rate_hz=";
constexpr size_t kMaxColumns = 10000;   // points present at once, far above any real volume
constexpr uint64_t kMaxFrameGap = 1u << 20;
constexpr size_t kMaxCells = 50'000'000;  // frames x columns of the table (1.2 GB of points)
constexpr size_t kMaxNameBytes = 256;
constexpr size_t kMaxNames = 10000;       // distinct names published, far above any marker set

[[noreturn]] void Fail(const std::string& path, size_t line, const std::string& why) {
  throw std::runtime_error(path + ":" + std::to_string(line) + ": " + why);
}

struct Row {
  uint64_t frame = 0;
  Eigen::Vector3d p;
  long long id = 0;
  int provisional = 0;
  int32_t name = -1;
};

bool ValidName(const std::string& name) {
  return !name.empty() && name.size() <= kMaxNameBytes &&
         std::none_of(name.begin(), name.end(), [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; });
}

}  // namespace

std::string LivePointsHeader(double rate_hz) {
  char buffer[96];
  std::snprintf(buffer, sizeof(buffer), "%s%.6g\n", kMagic, rate_hz);
  return buffer;
}

std::string LivePointLine(uint64_t frame, double x, double y, double z, long long id, bool provisional, int views,
                          double rms_px, const std::string& name) {
  if (!name.empty() && (!ValidName(name) || name.front() == ' ' || name.back() == ' '))
    throw std::invalid_argument("live point name '" + name + "': must be 1-256 characters without control characters "
                                "or outer spaces");
  char buffer[160];
  std::snprintf(buffer, sizeof(buffer), "%" PRIu64 "\t%.3f\t%.3f\t%.3f\t%lld\t%d\t%d\t%.3f", frame, x, y, z, id,
                provisional ? 1 : 0, views, rms_px);
  std::string line = buffer;
  if (!name.empty()) line += '\t' + name;
  line += '\n';
  return line;
}

LivePoints ReadLivePoints(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open for reading");
  return ParseLivePoints(in, path);
}

LivePoints ParseLivePoints(std::istream& in, const std::string& path) {
  std::string text;
  size_t line = 1;
  if (ReadBoundedLine(in, &text, kMaxTextLineBytes) != LineRead::kLine || text.rfind(kMagic, 0) != 0)
    Fail(path, 1, "not a live points file (header)");
  LivePoints live;
  MarkerTrajectories& out = live.points;
  std::map<std::string, int32_t> name_index;
  try {
    out.rate_hz = std::stod(text.substr(std::string(kMagic).size()));
  } catch (const std::exception&) {
    Fail(path, 1, "no rate in the header");
  }
  if (!(out.rate_hz > 0.0 && out.rate_hz <= 100000.0)) Fail(path, 1, "rate out of range");

  // Rows first (columns are known only at the end), then the frame-major table.
  std::vector<Row> rows;
  std::vector<size_t> pool_column;                          // per row (provisional rows)
  std::set<long long> confirmed;                            // marker ids seen
  std::map<long long, size_t> column_of_track;              // provisional id -> pool column
  std::vector<uint64_t> last_used;                          // per pool column
  uint64_t last_frame = 0;
  bool any = false;
  for (LineRead read; (read = ReadBoundedLine(in, &text, kMaxTextLineBytes)) != LineRead::kEnd;) {
    ++line;
    if (read == LineRead::kTooLong) Fail(path, line, "longer than 1 MiB: not a live points row");
    if (text.empty() || text[0] == '#') continue;
    std::istringstream fields(text);
    Row r;
    int views = 0;
    double rms = 0;
    if (!(fields >> r.frame >> r.p.x() >> r.p.y() >> r.p.z() >> r.id >> r.provisional >> views >> rms))
      Fail(path, line, "expected frame x y z id provisional views rms_px");
    std::string name;
    std::getline(fields, name);
    const size_t first = name.find_first_not_of(" \t\r");
    name = first == std::string::npos ? std::string() : name.substr(first, name.find_last_not_of(" \t\r") + 1 - first);
    if (!name.empty()) {
      if (!ValidName(name)) Fail(path, line, "a name must be 1-256 characters without control characters");
      const auto [it, added] = name_index.emplace(name, static_cast<int32_t>(live.identity.names.size()));
      if (added) {
        if (live.identity.names.size() >= kMaxNames) Fail(path, line, "more than 10000 distinct names");
        live.identity.names.push_back(name);
      }
      r.name = it->second;
    }
    if (!r.p.allFinite()) Fail(path, line, "coordinates must be finite");
    if (r.provisional != 0 && r.provisional != 1) Fail(path, line, "provisional must be 0 or 1");
    if (any && r.frame < last_frame) Fail(path, line, "frames must not go back");
    if (any && r.frame - last_frame > kMaxFrameGap) Fail(path, line, "implausible jump in frame numbers");
    any = true;
    last_frame = r.frame;
    size_t column = 0;
    if (!r.provisional) {
      if (r.id < 0 || r.id >= static_cast<long long>(kMaxColumns)) Fail(path, line, "marker id out of range");
      confirmed.insert(r.id);
    } else {
      if (r.id < -1 || r.id > (1LL << 60)) Fail(path, line, "track serial out of range");
      // A provisional track keeps its column while it is seen (a frame's miss included); a
      // column is free again once unused for more than a frame. An untracked point (-1) takes
      // any free column for its one frame.
      auto known = r.id >= 0 ? column_of_track.find(r.id) : column_of_track.end();
      if (known != column_of_track.end() && last_used[known->second] + 1 >= r.frame &&
          last_used[known->second] != r.frame) {
        column = known->second;
      } else {
        column = last_used.size();
        for (size_t c = 0; c < last_used.size(); ++c) {
          if (last_used[c] + 1 < r.frame) {
            column = c;
            break;
          }
        }
        if (column == last_used.size()) {
          if (last_used.size() >= kMaxColumns) Fail(path, line, "too many provisional points at once");
          last_used.push_back(0);
        }
        if (r.id >= 0) column_of_track[r.id] = column;
      }
      last_used[column] = r.frame;
    }
    pool_column.push_back(column);
    rows.push_back(r);
  }
  std::map<long long, size_t> confirmed_index;
  for (long long id : confirmed) {
    confirmed_index[id] = out.names.size();
    out.names.push_back(DefaultMarkerName(static_cast<size_t>(id)));
  }
  const size_t pool_base = out.names.size();
  for (size_t c = 0; c < last_used.size(); ++c) out.names.push_back("P" + std::to_string(c + 1));
  size_t frames = 0;
  for (size_t i = 0; i < rows.size(); ++i) frames += i == 0 || rows[i].frame != rows[i - 1].frame;
  if (frames * out.names.size() > kMaxCells)
    Fail(path, line, std::to_string(frames) + " frames x " + std::to_string(out.names.size()) + " columns is too large");
  for (size_t i = 0; i < rows.size(); ++i) {
    const Row& r = rows[i];
    if (out.frame_numbers.empty() || out.frame_numbers.back() != r.frame) {
      out.AddFrame(r.frame);
      live.identity.track.resize(out.points.size(), -1);
      live.identity.name.resize(out.points.size(), -1);
    }
    const size_t column = r.provisional ? pool_base + pool_column[i] : confirmed_index[r.id];
    const size_t cell = (out.NumFrames() - 1) * out.NumMarkers() + column;
    out.points[cell] = r.p;
    live.identity.track[cell] = r.id < 0 ? -1 : 2 * static_cast<int64_t>(r.id) + (r.provisional ? 1 : 0);
    live.identity.name[cell] = r.name;
  }
  return live;
}

}  // namespace mocap
