// TRC reading (tolerant of the variations real files show) and writing (strict OpenSim layout:
// tab after every value, empty cells for gaps, Time = frame number / rate).
#include "io/trc.h"

#include <algorithm>
#include <cerrno>
#include <cinttypes>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include "util/bounded_line.h"

namespace mocap {
namespace {

constexpr size_t kMaxMarkers = 100000;
// NumFrames and friends are written as fixed-width fields so Close can patch them in place.
constexpr int kPatchWidth = 12;

std::vector<std::string> SplitTabs(const std::string& line) {
  std::vector<std::string> cells;
  size_t start = 0;
  while (true) {
    const size_t tab = line.find('\t', start);
    if (tab == std::string::npos) {
      cells.push_back(line.substr(start));
      return cells;
    }
    cells.push_back(line.substr(start, tab - start));
    start = tab + 1;
  }
}

std::string Trim(const std::string& text) {
  const char* spaces = " \t\r\n\v\f";
  const size_t begin = text.find_first_not_of(spaces);
  if (begin == std::string::npos) return "";
  const size_t end = text.find_last_not_of(spaces);
  return text.substr(begin, end - begin + 1);
}

// Parses the whole (trimmed) cell as a number; false for empty or malformed cells.
bool ParseDouble(const std::string& cell, double* value) {
  const std::string text = Trim(cell);
  if (text.empty()) return false;
  char* end = nullptr;
  errno = 0;
  const double parsed = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || errno == ERANGE) return false;
  *value = parsed;
  return true;
}

bool IsBlank(const std::string& line) { return Trim(line).empty(); }

// Lines from a stream, ending at \n, \r\n or a lone \r, counted for error messages. A line
// over kMaxTextLineBytes (no TRC row comes near: 1000 markers make ~40 KiB) is refused naming
// it: /dev/zero or a damaged file would otherwise grow one line without end.
class LineReader {
 public:
  LineReader(std::istream& in, const std::string& source) : buffer_(in.rdbuf()), source_(source) {}

  bool Next(std::string* line) {
    line->clear();
    if (buffer_ == nullptr) return false;
    int c = buffer_->sbumpc();
    if (c == EOF) return false;
    while (c != EOF && c != '\n' && c != '\r') {
      if (line->size() >= kMaxTextLineBytes) {
        throw std::runtime_error(source_ + ": line " + std::to_string(number_ + 1) +
                                 ": longer than 1 MiB: not a TRC file");
      }
      line->push_back(static_cast<char>(c));
      c = buffer_->sbumpc();
    }
    if (c == '\r' && buffer_->sgetc() == '\n') {
      buffer_->sbumpc();
      ++bytes_;
    }
    bytes_ += line->size() + (c != EOF ? 1 : 0);
    terminated_ = c != EOF;
    ++number_;
    return true;
  }

  bool NextNonBlank(std::string* line) {
    while (Next(line)) {
      if (!IsBlank(*line)) return true;
    }
    return false;
  }

  size_t number() const { return number_; }
  // Bytes consumed so far (line ends included).
  size_t bytes() const { return bytes_; }
  // Whether the last line read ended with a line break (false: the file ends inside it).
  bool terminated() const { return terminated_; }

 private:
  std::streambuf* buffer_;
  const std::string& source_;
  size_t number_ = 0;
  size_t bytes_ = 0;
  bool terminated_ = true;
};

class TrcParser {
 public:
  TrcParser(const std::string& source, const TrcReadOptions& options)
      : source_(source), options_(options) {}

  MarkerTrajectories Parse(std::istream& in) {
    LineReader reader(in, source_);
    std::string line, values;
    if (!reader.NextNonBlank(&line) || Trim(line).rfind("PathFileType", 0) != 0) {
      Fail(std::max<size_t>(reader.number(), 1), "not a TRC file (first line must start with PathFileType)");
    }
    if (!reader.NextNonBlank(&line) || !reader.NextNonBlank(&values)) Fail(reader.number(), "header ends early");
    ParseHeader(line, values, reader.number());

    if (!reader.NextNonBlank(&line)) Fail(reader.number(), "missing the marker name row");
    ParseNames(line, reader.number());

    // The X1 Y1 Z1 row is optional in the wild; recognise it by its first label.
    if (reader.NextNonBlank(&line)) {
      const size_t first = line.find_first_not_of(" \t");
      if (first == std::string::npos || (line[first] != 'X' && line[first] != 'x')) ParseDataRow(line, reader);
      while (reader.NextNonBlank(&line)) ParseDataRow(line, reader);
    }
    Compact();
    AssignFrameNumbers();
    return std::move(result_);
  }

 private:
  [[noreturn]] void Fail(size_t line, const std::string& reason) const {
    throw std::runtime_error(source_ + ": line " + std::to_string(line) + ": " + reason);
  }

  void ParseHeader(const std::string& keys_line, const std::string& values_line, size_t line) {
    const std::vector<std::string> keys = SplitTabs(keys_line);
    const std::vector<std::string> values = SplitTabs(values_line);
    std::map<std::string, std::string> header;
    for (size_t i = 0; i < keys.size() && i < values.size(); ++i) {
      const std::string key = Trim(keys[i]);
      if (!key.empty()) header[key] = Trim(values[i]);
    }
    double rate = 0.0;
    if (!ParseDouble(header["DataRate"], &rate) && !ParseDouble(header["CameraRate"], &rate)) {
      Fail(line, "missing or malformed DataRate");
    }
    if (!(rate > 0.0) || !std::isfinite(rate)) Fail(line, "DataRate must be positive");
    result_.rate_hz = rate;

    double markers = 0.0;
    if (ParseDouble(header["NumMarkers"], &markers)) {
      if (markers < 0.0 || markers > kMaxMarkers || markers != std::floor(markers)) {
        Fail(line, "NumMarkers out of range");
      }
      header_markers_ = static_cast<size_t>(markers);
    }

    const std::string units = header["Units"];
    if (units.empty() || units == "mm") {
      scale_ = 1.0;
    } else if (units == "m") {
      scale_ = options_.convert_to_mm ? 1000.0 : 1.0;
    } else if (units == "cm") {
      scale_ = options_.convert_to_mm ? 10.0 : 1.0;
    } else {
      Fail(line, "unsupported Units \"" + units + "\" (mm, cm or m)");
    }
  }

  void ParseNames(const std::string& line_text, size_t line) {
    const std::vector<std::string> cells = SplitTabs(line_text);
    if (cells.empty() || Trim(cells[0]).rfind("Frame", 0) != 0) {
      Fail(line, "marker name row must start with Frame#");
    }
    std::vector<std::string> names;
    for (size_t i = 2; i < cells.size(); i += 3) {
      const std::string name = Trim(cells[i]);
      if (!name.empty()) {
        if (names.size() >= kMaxMarkers) Fail(line, "too many markers");
        // Names sit every third cell; a name elsewhere means the row is misaligned.
        names.push_back(name);
      }
      for (size_t j = i + 1; j < i + 3 && j < cells.size(); ++j) {
        if (!Trim(cells[j]).empty()) Fail(line, "marker names must be three columns apart");
      }
    }
    // NumMarkers only permits unnamed markers past a short name row; how many there are comes
    // from the data rows (a header is a claim: 100000 costs nothing unless the rows hold them).
    max_markers_ = std::max(names.size(), header_markers_);
    markers_ = names.size();
    stride_ = markers_;
    result_.names = std::move(names);
  }

  // Widens the row layout to `markers`; the stride doubles so that rows widening one marker at a
  // time cost amortised linear copying, and Compact() drops the slack at the end.
  void Widen(size_t markers, size_t line, size_t bytes_read) {
    if (markers <= markers_) return;
    const size_t frames = frame_column_.size();
    CheckBudget(frames, markers, line, bytes_read);
    if (markers > stride_) {
      const size_t stride = std::max(markers, std::min(max_markers_, 2 * stride_));
      std::vector<Eigen::Vector3d> points(frames * stride, MarkerTrajectories::Gap());
      for (size_t f = 0; f < frames; ++f) {
        std::copy_n(result_.points.begin() + static_cast<long>(f * stride_), markers_,
                    points.begin() + static_cast<long>(f * stride));
      }
      result_.points = std::move(points);
      stride_ = stride;
    }
    markers_ = markers;
  }

  // The dense frames x markers table may not outgrow the text that fills it by more than a
  // fixed factor: rows that leave their trailing cells out are legal, so one wide row followed
  // by a million empty ones would otherwise cost a million wide rows of memory.
  void CheckBudget(size_t frames, size_t markers, size_t line, size_t bytes_read) const {
    constexpr size_t kPointsPerByte = 2;
    constexpr size_t kFreePoints = size_t{1} << 20;
    if (frames * markers > kFreePoints + kPointsPerByte * bytes_read) {
      Fail(line, std::to_string(frames) + " frames x " + std::to_string(markers) + " markers is more than " +
                     std::to_string(kPointsPerByte) + " points per byte of the " + std::to_string(bytes_read) +
                     " bytes read: the rows are too short for their width");
    }
  }

  // Drops the stride's slack and names the unnamed markers the data rows hold.
  void Compact() {
    const size_t frames = frame_column_.size();
    if (stride_ != markers_) {
      for (size_t f = 1; f < frames; ++f) {
        std::copy_n(result_.points.begin() + static_cast<long>(f * stride_), markers_,
                    result_.points.begin() + static_cast<long>(f * markers_));
      }
    }
    result_.points.resize(frames * markers_);
    for (size_t i = result_.names.size(); i < markers_; ++i) result_.names.push_back(DefaultMarkerName(i));
  }

  // A last row without its line break that is also short of cells is a file cut off while it
  // was written or copied: refused as such, not read as a frame whose last markers are gaps.
  // (Short rows that end in a line break are a writer leaving out empty trailing cells, and are
  // read; a cut inside the last cell of a full row cannot be told from a shorter number.)
  void ParseDataRow(const std::string& text, const LineReader& reader) {
    if (!reader.terminated()) {
      const size_t cells = 1 + static_cast<size_t>(std::count(text.begin(), text.end(), '\t'));
      const size_t columns = 2 + 3 * result_.names.size();
      if (cells < columns)
        Fail(reader.number(), "the file ends inside this row (" + std::to_string(cells) + " of " +
                                  std::to_string(columns) + " cells, no line end): it was cut off; remove the "
                                  "partial row to read the rest");
    }
    ParseRow(text, reader.number(), reader.bytes());
  }

  // Data rows are most of a file: cells are scanned in place, without copies.
  void ParseRow(const std::string& text, size_t line, size_t bytes_read) {
    const size_t columns = 2 + 3 * max_markers_;
    size_t column = 0;
    size_t position = 0;
    double frame = 0.0;
    double time = std::nan("");
    row_.clear();
    Eigen::Vector3d point;
    int present = 0;
    bool any_cell = true;
    while (any_cell) {
      size_t end = text.find('\t', position);
      if (end == std::string::npos) {
        end = text.size();
        any_cell = false;
      }
      // Trim spaces (padding) around the cell.
      size_t begin = position;
      while (begin < end && (text[begin] == ' ' || text[begin] == '\v' || text[begin] == '\f')) ++begin;
      size_t stop = end;
      while (stop > begin && (text[stop - 1] == ' ' || text[stop - 1] == '\v' || text[stop - 1] == '\f')) --stop;
      position = end + 1;
      const bool empty = begin == stop;
      double value = 0.0;
      if (!empty) {
        if (column >= columns) Fail(line, "more values than the " + std::to_string(max_markers_) + " markers");
        char* parsed_end = nullptr;
        errno = 0;
        value = std::strtod(text.c_str() + begin, &parsed_end);
        if (parsed_end != text.c_str() + stop || errno == ERANGE) {
          if (column == 0) Fail(line, "Frame# must be a non-negative integer");
          if (column == 1) Fail(line, "malformed Time");
          Fail(line, "malformed coordinate \"" + text.substr(begin, stop - begin) + "\" in column " +
                         std::to_string(column + 1));
        }
      }
      if (column == 0) {
        if (empty || value != std::floor(value) || value < 0.0 || value > 1e15) {
          Fail(line, "Frame# must be a non-negative integer");
        }
        frame = value;
      } else if (column == 1) {
        if (!empty && !std::isfinite(value)) Fail(line, "malformed Time");
        if (!empty) time = value;
      } else if (column < columns) {
        const size_t axis = (column - 2) % 3;
        if (axis == 0) present = 0;
        if (!empty) {
          point[axis] = value * scale_;
          ++present;
        }
        // A partly empty marker is a gap: no tool writes one on purpose. NaN text stays NaN.
        if (axis == 2 && present == 3 && point.allFinite() && !(options_.zero_is_gap && point.isZero(0.0))) {
          row_.emplace_back((column - 2) / 3, point);
        }
        // Any value, even a NaN or half a point, makes its marker part of the file's width.
        if (!empty) widest_ = std::max(widest_, (column - 2) / 3 + 1);
      }
      ++column;
    }
    Widen(widest_, line, bytes_read);
    const size_t frames = frame_column_.size() + 1;
    CheckBudget(frames, markers_, line, bytes_read);
    result_.points.resize(frames * stride_, MarkerTrajectories::Gap());
    Eigen::Vector3d* row = result_.points.data() + (frames - 1) * stride_;
    for (const auto& [marker, value] : row_) row[marker] = value;
    frame_column_.push_back(static_cast<uint64_t>(frame));
    result_.frame_numbers.push_back(0);
    time_column_.push_back(time);
  }

  void AssignFrameNumbers() {
    const size_t frames = frame_column_.size();
    bool time_usable = true;
    for (size_t i = 0; i < frames && time_usable; ++i) {
      const double scaled = time_column_[i] * result_.rate_hz;
      if (!std::isfinite(scaled) || scaled < -0.5 || scaled > 1e15) {
        time_usable = false;
      } else {
        result_.frame_numbers[i] = static_cast<uint64_t>(std::llround(scaled));
        if (i > 0 && result_.frame_numbers[i] <= result_.frame_numbers[i - 1]) time_usable = false;
      }
    }
    if (time_usable) return;
    // Time missing, negative or too coarse to separate frames: fall back on Frame#, 1-based.
    for (size_t i = 0; i < frames; ++i) {
      result_.frame_numbers[i] = frame_column_[i] > 0 ? frame_column_[i] - 1 : 0;
      if (i > 0 && result_.frame_numbers[i] <= result_.frame_numbers[i - 1]) {
        throw std::runtime_error(source_ + ": frames are not in increasing order (Time and Frame# both)");
      }
    }
  }

  const std::string& source_;
  const TrcReadOptions& options_;
  MarkerTrajectories result_;
  size_t header_markers_ = 0;
  size_t max_markers_ = 0;  // the name row's count, or NumMarkers when that is more
  size_t markers_ = 0;      // the width the rows have shown so far
  size_t stride_ = 0;       // points per stored row (markers_ plus slack)
  size_t widest_ = 0;
  std::vector<std::pair<size_t, Eigen::Vector3d>> row_;
  double scale_ = 1.0;
  std::vector<uint64_t> frame_column_;
  std::vector<double> time_column_;
};

std::string BaseName(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

}  // namespace

MarkerTrajectories ParseTrc(const std::string& text, const std::string& source,
                            const TrcReadOptions& options) {
  std::istringstream in(text);
  return TrcParser(source, options).Parse(in);
}

MarkerTrajectories ReadTrc(const std::string& path, const TrcReadOptions& options) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open for reading");
  MarkerTrajectories result = TrcParser(path, options).Parse(in);
  if (in.bad()) throw std::runtime_error(path + ": read failed");
  return result;
}

TrcWriter::~TrcWriter() {
  if (file_ != nullptr) {
    // Destructors must not throw; an explicit Close() reports errors.
    try {
      Close();
    } catch (const std::exception&) {
    }
  }
}

void TrcWriter::Fail(const std::string& reason) const {
  throw std::runtime_error(path_ + ": " + reason);
}

void TrcWriter::Open(const std::string& path, const std::vector<std::string>& names, double rate_hz) {
  if (file_ != nullptr) Close();
  path_ = path;
  if (!(rate_hz > 0.0) || !std::isfinite(rate_hz)) Fail("TRC rate must be positive");
  for (const std::string& name : names) {
    if (name.empty() || name.find_first_of("\t\r\n") != std::string::npos) {
      Fail("marker name \"" + name + "\" is empty or holds a tab or newline");
    }
  }
  file_ = std::fopen(path.c_str(), "wb");
  if (file_ == nullptr) Fail(std::string("cannot open for writing (") + std::strerror(errno) + ")");
  num_markers_ = names.size();
  rate_hz_ = rate_hz;
  frames_ = 0;

  std::fprintf(file_, "PathFileType\t4\t(X/Y/Z)\t%s\t\n", BaseName(path).c_str());
  std::fprintf(file_,
               "DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\tOrigDataRate\tOrigDataStartFrame\t"
               "OrigNumFrames\t\n");
  std::fprintf(file_, "%.6g\t%.6g\t", rate_hz, rate_hz);
  num_frames_offset_ = std::ftell(file_);
  std::fprintf(file_, "%*d\t%zu\tmm\t%.6g\t", kPatchWidth, 0, num_markers_, rate_hz);
  start_frame_offset_ = std::ftell(file_);
  std::fprintf(file_, "%*d\t", kPatchWidth, 1);
  orig_num_frames_offset_ = std::ftell(file_);
  std::fprintf(file_, "%*d\t\n", kPatchWidth, 0);
  std::fprintf(file_, "Frame#\tTime\t");
  for (const std::string& name : names) std::fprintf(file_, "%s\t\t\t", name.c_str());
  std::fprintf(file_, "\n\t\t");
  for (size_t m = 1; m <= num_markers_; ++m) std::fprintf(file_, "X%zu\tY%zu\tZ%zu\t", m, m, m);
  std::fprintf(file_, "\n\n");
  if (std::fflush(file_) != 0 || std::ferror(file_)) Fail("write failed");
}

void TrcWriter::WriteFrame(uint64_t frame_number, const Eigen::Vector3d* points, size_t count) {
  if (file_ == nullptr) throw std::logic_error("TrcWriter::WriteFrame before Open");
  if (count != num_markers_) {
    Fail("frame has " + std::to_string(count) + " markers, the file " + std::to_string(num_markers_));
  }
  if (frames_ > 0 && frame_number <= last_frame_) Fail("frames must be written in increasing order");
  if (frames_ == 0) first_frame_ = frame_number;
  last_frame_ = frame_number;
  ++frames_;
  // Frame# is 1-based as in OpenSim's files; Time carries the global frame number.
  std::fprintf(file_, "%" PRIu64 "\t%.6f\t", frame_number + 1, static_cast<double>(frame_number) / rate_hz_);
  for (size_t m = 0; m < count; ++m) {
    const Eigen::Vector3d& p = points[m];
    if (MarkerTrajectories::IsGap(p)) {
      std::fputs("\t\t\t", file_);
    } else {
      std::fprintf(file_, "%.5f\t%.5f\t%.5f\t", p.x(), p.y(), p.z());
    }
  }
  std::fputc('\n', file_);
  if (std::fflush(file_) != 0 || std::ferror(file_)) Fail("write failed");
}

void TrcWriter::Close() {
  if (file_ == nullptr) return;
  std::FILE* file = file_;
  file_ = nullptr;
  bool ok = true;
  const auto patch = [&](long offset, uint64_t value) {
    ok = ok && std::fseek(file, offset, SEEK_SET) == 0 &&
         std::fprintf(file, "%*" PRIu64, kPatchWidth, value) == kPatchWidth;
  };
  patch(num_frames_offset_, frames_);
  patch(start_frame_offset_, frames_ > 0 ? first_frame_ + 1 : 1);
  patch(orig_num_frames_offset_, frames_);
  ok = std::fclose(file) == 0 && ok;
  if (!ok) Fail("write failed while finishing the file");
}

void WriteTrc(const MarkerTrajectories& trajectories, const std::string& path) {
  if (trajectories.points.size() != trajectories.NumFrames() * trajectories.NumMarkers()) {
    throw std::logic_error("WriteTrc: points do not match frames x markers");
  }
  TrcWriter writer;
  writer.Open(path, trajectories.names, trajectories.rate_hz);
  for (size_t f = 0; f < trajectories.NumFrames(); ++f) {
    writer.WriteFrame(trajectories.frame_numbers[f], trajectories.points.data() + f * trajectories.NumMarkers(),
                      trajectories.NumMarkers());
  }
  writer.Close();
}

}  // namespace mocap
