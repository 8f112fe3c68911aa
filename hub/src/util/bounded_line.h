// Line reading with a bound: std::getline grows one line as long as its input has no newline,
// which /dev/zero, a FIFO or a damaged file never gives. Every line-oriented reader of outside
// files reads through this, so a bad file costs at most max_bytes of memory and a clear error.
#pragma once

#include <istream>
#include <string>

namespace mocap {

enum class LineRead { kLine, kEnd, kTooLong };

// One line into *line, without its '\n'. kEnd: the input ended with nothing read. kTooLong: the
// line reached max_bytes without a newline (*line holds those bytes, the rest is not read).
inline LineRead ReadBoundedLine(std::istream& in, std::string* line, size_t max_bytes) {
  line->clear();
  std::streambuf* buffer = in.rdbuf();
  if (buffer == nullptr || !in.good()) return LineRead::kEnd;
  for (;;) {
    const int c = buffer->sbumpc();
    if (c == std::char_traits<char>::eof()) {
      in.setstate(std::ios::eofbit);
      return line->empty() ? LineRead::kEnd : LineRead::kLine;
    }
    if (c == '\n') return LineRead::kLine;
    if (line->size() >= max_bytes) return LineRead::kTooLong;
    line->push_back(static_cast<char>(c));
  }
}

// The bound the hub's text readers use: no line of theirs comes near it (a live points row of
// 1000 markers is ~40 KiB).
constexpr size_t kMaxTextLineBytes = 1 << 20;

}  // namespace mocap
