// Line-oriented .mcd parser: header, camera blocks, then frames; every error names its line.
#include "calib/mcd.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "util/regular_file.h"

namespace mocap {
namespace {

class Lines {
 public:
  Lines(const std::string& text, const std::string& source) : source_(source) {
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
      if (!line.empty() && line.back() == '\r') line.pop_back();
      lines_.push_back(line);
    }
  }
  bool Done() const { return next_ >= lines_.size(); }
  const std::string& Take() { return lines_[next_++]; }
  static bool Blank(const std::string& line) { return line.find_first_not_of(" \t") == std::string::npos; }
  void SkipBlank() {
    while (!Done() && Blank(lines_[next_])) ++next_;
  }
  [[noreturn]] void Fail(const std::string& what) const {
    throw std::runtime_error(source_ + ":" + std::to_string(next_) + ": " + what);
  }
  std::string Where() const { return source_ + ":" + std::to_string(next_); }

 private:
  std::string source_;
  std::vector<std::string> lines_;
  size_t next_ = 0;
};

// "marksCount: M x = X y = Y x = X y = Y ..."
std::vector<Blob> ParseMarks(const std::string& line, Lines* lines) {
  std::istringstream in(line);
  std::string word;
  long count = -1;
  if (!(in >> word) || word != "marksCount:" || !(in >> count) || count < 0 || count > 100000) {
    lines->Fail("expected 'marksCount: N x = .. y = ..', got '" + line + "'");
  }
  std::vector<Blob> blobs;
  for (long i = 0; i < count; ++i) {
    std::string x_name, x_eq, y_name, y_eq;
    double x = 0.0, y = 0.0;
    if (!(in >> x_name >> x_eq >> x >> y_name >> y_eq >> y) || x_name != "x" || x_eq != "=" || y_name != "y" ||
        y_eq != "=" || !std::isfinite(x) || !std::isfinite(y)) {
      lines->Fail("marksCount says " + std::to_string(count) + " marks but mark " + std::to_string(i + 1) +
                  " is not 'x = X y = Y'");
    }
    Blob blob;
    blob.pixel = Eigen::Vector2d(x, y);
    // .mcd records positions only; the wire format needs a blob size, so a mark counts as one
    // full-brightness pixel.
    blob.area = 1;
    blob.peak = 255;
    blob.mean = 255;
    blobs.push_back(blob);
  }
  if (in >> word) lines->Fail("more marks than marksCount says: '" + word + "'");
  return blobs;
}

}  // namespace

McdRecording ParseMcd(const std::string& text, const std::string& source) {
  Lines lines(text, source);
  McdRecording recording;
  lines.SkipBlank();
  if (lines.Done()) lines.Fail("empty file");
  long camera_count = 0;
  {
    std::istringstream in(lines.Take());
    std::string word, extra;
    if (!(in >> word >> camera_count) || word != "CameraCount:" || (in >> extra)) {
      lines.Fail("the first line must be 'CameraCount: N'");
    }
    if (camera_count < 1 || camera_count > 1024) lines.Fail("CameraCount must be 1..1024");
  }
  for (long c = 0; c < camera_count; ++c) {
    lines.SkipBlank();
    const std::string where = lines.Where();
    std::vector<std::string> block;
    while (!lines.Done() && block.size() < 19) {
      const std::string& line = lines.Take();
      if (Lines::Blank(line)) break;
      block.push_back(line);
    }
    recording.cameras.push_back(ParseTsaiBlock(block, where + " (camera " + std::to_string(c + 1) + ")"));
  }
  lines.SkipBlank();
  while (!lines.Done()) {
    const std::string header = lines.Take();
    if (Lines::Blank(header)) continue;
    std::istringstream in(header);
    std::string word, extra;
    long long number = -1;
    if (!(in >> word >> number) || word != "Frame:" || number < 0 || (in >> extra)) {
      lines.Fail("expected 'Frame: K', got '" + header + "'");
    }
    FrameSet set;
    set.frame_number = static_cast<uint64_t>(number);
    if (!recording.frames.empty() && set.frame_number <= recording.frames.back().frame_number) {
      lines.Fail("frame numbers must increase");
    }
    for (long c = 0; c < camera_count; ++c) {
      if (lines.Done()) {
        lines.Fail("frame " + std::to_string(number) + " ends before its camera " + std::to_string(c + 1));
      }
      CameraFrame frame;
      frame.camera_id = static_cast<uint32_t>(c + 1);
      frame.frame_number = set.frame_number;
      frame.blobs = ParseMarks(lines.Take(), &lines);
      set.cameras.push_back(std::move(frame));
    }
    recording.frames.push_back(std::move(set));
  }
  return recording;
}

McdRecording ReadMcd(const std::string& path) {
  return ParseMcd(ReadRegularFile(path, kMaxRecordingFileBytes, "an .mcd recording"), path);
}

}  // namespace mocap
