// The raw 2D log of a session: every datagram as received, append-only and replayable.
// File layout (little-endian): "MOCAPLOG" u32 version=1 u32 reserved, then records
//   u32 magic 0x3152434D ("MCR1") | u32 payload length | u64 receive time ns | u32 CRC-32 of
//   (time bytes + payload) | payload
// The record magic is the sync marker: a record is good only when its magic, a length of at most
// 64 KiB and its CRC all agree. A crash leaves at most one torn record at the end; damage
// elsewhere (a flipped bit, a lost block) costs only the records it touches: the reader skips to
// the next offset where a good record starts (a false start needs a 32-bit CRC to match by
// chance) and counts the damaged stretches and their bytes. Resynchronising verifies at most one
// 64 KiB record per magic found in the damaged stretch, so reading stays linear in the file size
// times that bound, and memory stays at one record plus a 256 KiB read buffer.
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
  // The errno of the last failed write or flush (ENOSPC: the disk is full), 0 when none failed.
  int error_number() const { return error_number_; }

 private:
  std::FILE* file_ = nullptr;
  std::string path_;
  uint64_t records_ = 0;
  int error_number_ = 0;
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

  // Throws std::runtime_error when the file cannot be opened or is not a session log (or has a
  // version this reader does not know: it says so rather than guessing).
  void Open(const std::string& path);
  // The next good record; false at the end of the file. Damaged stretches on the way are skipped
  // and counted; warning() then describes them.
  bool Next(LogRecord* record);
  // Empty when every byte belonged to a good record; otherwise one line: the damaged stretches
  // skipped, their bytes, where the first began and why, and a torn record at the end.
  std::string warning() const;
  uint64_t records() const { return records_; }
  uint64_t damaged_stretches() const { return damaged_stretches_; }  // torn tail included
  uint64_t skipped_bytes() const { return skipped_bytes_; }
  bool torn_tail() const { return torn_tail_; }

 private:
  enum class Check { kGood, kBad, kShort };
  // Makes at least n bytes from pos_ available in buffer_ when the file has them; returns how
  // many are.
  size_t Available(size_t n);
  // Whether a good record starts at pos_ (kShort: the file ends inside it); why says what is
  // wrong with a bad one.
  Check CheckRecord(uint32_t* size, const char** why);
  // Moves pos_ to the next offset where a good record starts, or to the end of the file.
  void Resynchronise(const char* why);

  std::FILE* file_ = nullptr;
  std::string path_;
  std::vector<uint8_t> buffer_;  // file bytes from buffer_offset_ on
  uint64_t buffer_offset_ = 0;
  uint64_t pos_ = 0;             // file offset of the next record
  uint64_t file_size_ = 0;       // at opening: sizes the reads
  bool eof_ = false;
  uint64_t records_ = 0;
  uint64_t damaged_stretches_ = 0;
  uint64_t skipped_bytes_ = 0;
  uint64_t first_damage_at_ = 0;
  std::string first_damage_why_;
  bool torn_tail_ = false;
  std::string torn_tail_why_;
  uint64_t torn_tail_at_ = 0;
  uint64_t torn_tail_bytes_ = 0;
};

}  // namespace mocap
