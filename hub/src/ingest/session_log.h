// The raw 2D log of a session: every datagram as received, append-only and replayable.
// File layout (little-endian): "MOCAPLOG" u32 version=1 u32 reserved, then records
//   u32 magic 0x3152434D ("MCR1") | u32 payload length | u64 receive time ns | u32 CRC-32 of
//   (time bytes + payload) | payload
// A crash leaves at most one torn record at the end; the reader stops at the first record that
// is short or fails its CRC and reports where, keeping everything before it.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace mocap {

class SessionLogWriter {
 public:
  SessionLogWriter() = default;
  ~SessionLogWriter();
  SessionLogWriter(const SessionLogWriter&) = delete;
  SessionLogWriter& operator=(const SessionLogWriter&) = delete;

  // Creates (truncates) the log. Throws std::runtime_error naming the file on failure.
  // exclusive: fail if the file exists (two writers never share a log).
  void Open(const std::string& path, bool exclusive = false);
  void Append(const uint8_t* data, size_t size, uint64_t receive_time_ns);
  // Pushes buffered records to the kernel so they survive a crash of this process.
  void Flush();
  void Close();
  uint64_t records() const { return records_; }

 private:
  std::FILE* file_ = nullptr;
  std::string path_;
  uint64_t records_ = 0;
};

struct LogRecord {
  uint64_t receive_time_ns = 0;
  std::vector<uint8_t> payload;
};

class SessionLogReader {
 public:
  SessionLogReader() = default;
  ~SessionLogReader();
  SessionLogReader(const SessionLogReader&) = delete;
  SessionLogReader& operator=(const SessionLogReader&) = delete;

  // Throws std::runtime_error when the file cannot be opened or is not a session log.
  void Open(const std::string& path);
  // False at the end of the good records; warning() then says whether the tail was damaged.
  bool Next(LogRecord* record);
  const std::string& warning() const { return warning_; }
  uint64_t records() const { return records_; }

 private:
  std::FILE* file_ = nullptr;
  std::string path_;
  std::string warning_;
  uint64_t records_ = 0;
  uint64_t offset_ = 0;
};

}  // namespace mocap
