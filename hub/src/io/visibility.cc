// Reading and writing visibility.tsv.
#include "io/visibility.h"

#include <algorithm>
#include <cerrno>
#include <cinttypes>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "util/bounded_line.h"

namespace mocap {
namespace {

constexpr const char* kHeaderComment = "# mocap visibility v1: cameras that delivered a blob of each marker";

std::vector<std::string> Split(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream in(line);
  for (std::string cell; std::getline(in, cell, '\t');) cells.push_back(cell);
  return cells;
}

bool ParseUnsigned(const std::string& text, uint64_t limit, uint64_t* value) {
  if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos) return false;
  errno = 0;
  const unsigned long long parsed = std::strtoull(text.c_str(), nullptr, 10);
  if (errno == ERANGE || parsed > limit) return false;
  *value = parsed;
  return true;
}

}  // namespace

MarkerVisibility ReadVisibility(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open for reading");
  const auto fail = [&](size_t line, const std::string& reason) {
    throw std::runtime_error(path + ": line " + std::to_string(line) + ": " + reason);
  };
  MarkerVisibility visibility;
  std::string line;
  size_t number = 0;
  bool have_header = false;
  for (LineRead read; (read = ReadBoundedLine(in, &line, kMaxTextLineBytes)) != LineRead::kEnd;) {
    ++number;
    if (read == LineRead::kTooLong) fail(number, "longer than 1 MiB: not a visibility file");
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    const std::vector<std::string> cells = Split(line);
    if (!have_header) {
      if (cells.empty() || cells[0] != "frame") fail(number, "header must start with \"frame\"");
      visibility.names.assign(cells.begin() + 1, cells.end());
      // A name the writer cannot put back as read (an empty last cell is no cell; text after a
      // NUL is lost) would shift every count to another marker: refused.
      for (size_t m = 0; m < visibility.names.size(); ++m) {
        const std::string& name = visibility.names[m];
        const bool control = std::any_of(name.begin(), name.end(), [](char c) {
          return static_cast<unsigned char>(c) < 0x20 || c == '\x7f';
        });
        if (name.empty() || control)
          fail(number, "marker " + std::to_string(m + 1) + "'s name is empty or holds a control character");
      }
      have_header = true;
      continue;
    }
    if (cells.size() != visibility.names.size() + 1) {
      fail(number, "expected " + std::to_string(visibility.names.size() + 1) + " cells");
    }
    uint64_t frame = 0;
    if (!ParseUnsigned(cells[0], UINT64_MAX, &frame)) fail(number, "bad frame number");
    if (!visibility.frame_numbers.empty() && frame <= visibility.frame_numbers.back()) {
      fail(number, "frame numbers must increase");
    }
    visibility.frame_numbers.push_back(frame);
    for (size_t m = 1; m < cells.size(); ++m) {
      uint64_t count = 0;
      if (!ParseUnsigned(cells[m], UINT16_MAX, &count)) fail(number, "bad camera count \"" + cells[m] + "\"");
      visibility.counts.push_back(static_cast<uint16_t>(count));
    }
  }
  if (in.bad()) throw std::runtime_error(path + ": read failed");
  if (!have_header) throw std::runtime_error(path + ": empty visibility file");
  return visibility;
}

VisibilityWriter::~VisibilityWriter() {
  if (file_ != nullptr) std::fclose(file_);
}

void VisibilityWriter::Open(const std::string& path, const std::vector<std::string>& names) {
  path_ = path;
  file_ = std::fopen(path.c_str(), "wb");
  if (file_ == nullptr) throw std::runtime_error(path + ": cannot open for writing (" + std::strerror(errno) + ")");
  num_markers_ = names.size();
  std::fprintf(file_, "%s\nframe", kHeaderComment);
  for (const std::string& name : names) std::fprintf(file_, "\t%s", name.c_str());
  std::fputc('\n', file_);
}

void VisibilityWriter::WriteFrame(uint64_t frame_number, const std::vector<int>& cameras_seeing) {
  if (file_ == nullptr) throw std::logic_error("VisibilityWriter::WriteFrame before Open");
  if (cameras_seeing.size() != num_markers_) throw std::logic_error("VisibilityWriter: wrong marker count");
  std::fprintf(file_, "%" PRIu64, frame_number);
  for (int count : cameras_seeing) std::fprintf(file_, "\t%d", count);
  std::fputc('\n', file_);
  if (std::fflush(file_) != 0) throw std::runtime_error(path_ + ": write failed");
}

void VisibilityWriter::Close() {
  if (file_ == nullptr) return;
  const bool ok = std::fclose(file_) == 0;
  file_ = nullptr;
  if (!ok) throw std::runtime_error(path_ + ": write failed");
}

}  // namespace mocap
