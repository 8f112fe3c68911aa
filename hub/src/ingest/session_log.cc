// Append-only datagram log with per-record CRC, read back past damage (format in session_log.h).
#include "ingest/session_log.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>

#include <zlib.h>

namespace mocap {
namespace {

constexpr char kFileMagic[8] = {'M', 'O', 'C', 'A', 'P', 'L', 'O', 'G'};
constexpr uint32_t kFileVersion = 1;
constexpr uint32_t kRecordMagic = 0x3152434D;
constexpr uint32_t kMaxPayload = 64 * 1024;
constexpr size_t kRecordHeader = 4 + 4 + 8 + 4;
constexpr size_t kReadChunk = 256 * 1024;
constexpr size_t kMinRead = 4096;
constexpr size_t kScanWindow = 4096;  // bytes searched for a magic per step while resynchronising

void PutU32(uint8_t* p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<uint8_t>(v >> (8 * i));
}
void PutU64(uint8_t* p, uint64_t v) {
  for (int i = 0; i < 8; ++i) p[i] = static_cast<uint8_t>(v >> (8 * i));
}
uint32_t GetU32(const uint8_t* p) {
  uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | p[i];
  return v;
}
uint64_t GetU64(const uint8_t* p) {
  uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = (v << 8) | p[i];
  return v;
}
uint32_t RecordCrc(const uint8_t* time_bytes, const uint8_t* payload, size_t size) {
  uLong crc = crc32(0L, Z_NULL, 0);
  crc = crc32(crc, time_bytes, 8);
  crc = crc32(crc, payload, static_cast<uInt>(size));
  return static_cast<uint32_t>(crc);
}

std::runtime_error IoError(const std::string& what, const std::string& path) {
  return std::runtime_error(path + ": " + what + ": " + std::strerror(errno));
}

}  // namespace

SessionLogWriter::~SessionLogWriter() {
  if (file_) std::fclose(file_);
}

void SessionLogWriter::Open(const std::string& path, bool exclusive) {
  path_ = path;
  file_ = std::fopen(path.c_str(), exclusive ? "wbx" : "wb");
  if (!file_) throw IoError("cannot create session log", path);
  uint8_t header[16];
  std::memcpy(header, kFileMagic, 8);
  PutU32(header + 8, kFileVersion);
  PutU32(header + 12, 0);
  if (std::fwrite(header, 1, sizeof header, file_) != sizeof header) throw IoError("write failed", path);
  Flush();
}

void SessionLogWriter::Append(const uint8_t* data, size_t size, uint64_t receive_time_ns) {
  if (!file_) throw std::logic_error("session log not open");
  if (size > kMaxPayload) throw std::invalid_argument("session log record too large");
  uint8_t header[kRecordHeader];
  PutU32(header, kRecordMagic);
  PutU32(header + 4, static_cast<uint32_t>(size));
  PutU64(header + 8, receive_time_ns);
  PutU32(header + 16, RecordCrc(header + 8, data, size));
  if (std::fwrite(header, 1, sizeof header, file_) != sizeof header ||
      std::fwrite(data, 1, size, file_) != size) {
    error_number_ = errno;
    throw IoError("write failed", path_);
  }
  ++records_;
}

void SessionLogWriter::Flush() {
  if (file_ && std::fflush(file_) != 0) {
    error_number_ = errno;
    throw IoError("flush failed", path_);
  }
}

void SessionLogWriter::Close() {
  if (!file_) return;
  Flush();
  std::fclose(file_);
  file_ = nullptr;
}

SessionLogReader::~SessionLogReader() {
  if (file_) std::fclose(file_);
}

void SessionLogReader::Open(const std::string& path) {
  path_ = path;
  file_ = std::fopen(path.c_str(), "rb");
  if (!file_) throw IoError("cannot open session log", path);
  uint8_t header[16];
  if (std::fread(header, 1, sizeof header, file_) != sizeof header ||
      std::memcmp(header, kFileMagic, 8) != 0)
    throw std::runtime_error(path + ": not a mocap session log");
  if (GetU32(header + 8) != kFileVersion)
    throw std::runtime_error(path + ": session log version " + std::to_string(GetU32(header + 8)) +
                             " is not one this mocap-hub reads (it reads version " + std::to_string(kFileVersion) +
                             "); use the mocap-hub that wrote it");
  buffer_offset_ = pos_ = sizeof header;
  // The size at opening only sizes the reads (a small log gets a small buffer); a log that grows
  // meanwhile is still read to its end.
  if (std::fseek(file_, 0, SEEK_END) == 0) {
    const long size = std::ftell(file_);
    file_size_ = size > 0 ? static_cast<uint64_t>(size) : 0;
  }
  if (std::fseek(file_, static_cast<long>(sizeof header), SEEK_SET) != 0) throw IoError("seek failed", path);
}

size_t SessionLogReader::Available(size_t n) {
  size_t start = static_cast<size_t>(pos_ - buffer_offset_);
  if (buffer_.size() - start >= n || eof_) return std::min(n, buffer_.size() - start);
  // Drop what was consumed before growing, so the buffer stays one read chunk plus one record.
  buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(start));
  buffer_offset_ = pos_;
  while (buffer_.size() < n && !eof_) {
    const size_t old = buffer_.size();
    const uint64_t end = buffer_offset_ + old;
    const uint64_t rest = file_size_ > end ? file_size_ - end : 0;
    const size_t want = std::max(n - old, static_cast<size_t>(std::clamp<uint64_t>(rest, kMinRead, kReadChunk)));
    buffer_.resize(old + want);
    const size_t got = std::fread(buffer_.data() + old, 1, want, file_);
    buffer_.resize(old + got);
    if (got < want) {
      if (std::ferror(file_)) throw IoError("read failed", path_);
      eof_ = true;
    }
  }
  return std::min(n, buffer_.size());
}

SessionLogReader::Check SessionLogReader::CheckRecord(uint32_t* size, const char** why) {
  if (Available(kRecordHeader) < kRecordHeader) {
    *why = "truncated record header";
    return Check::kShort;
  }
  const uint8_t* header = buffer_.data() + (pos_ - buffer_offset_);
  if (GetU32(header) != kRecordMagic) {
    *why = "bad record magic";
    return Check::kBad;
  }
  *size = GetU32(header + 4);
  if (*size > kMaxPayload) {
    *why = "impossible record length";
    return Check::kBad;
  }
  if (Available(kRecordHeader + *size) < kRecordHeader + *size) {
    *why = "truncated record";
    return Check::kShort;
  }
  header = buffer_.data() + (pos_ - buffer_offset_);  // the buffer may have moved
  if (RecordCrc(header + 8, header + kRecordHeader, *size) != GetU32(header + 16)) {
    *why = "CRC mismatch";
    return Check::kBad;
  }
  return Check::kGood;
}

void SessionLogReader::Resynchronise(const char* why) {
  static constexpr uint8_t kMagicBytes[4] = {0x4D, 0x43, 0x52, 0x31};  // kRecordMagic, little-endian
  const uint64_t start = pos_++;
  for (;;) {
    const size_t available = Available(kScanWindow);
    const uint8_t* begin = buffer_.data() + (pos_ - buffer_offset_);
    const uint8_t* found = std::search(begin, begin + available, kMagicBytes, kMagicBytes + 4);
    if (found == begin + available) {
      if (available < kScanWindow) {  // the end of the file: nothing good after the damage
        pos_ += available;
        break;
      }
      pos_ += available - 3;  // a magic may straddle the chunk's end
      continue;
    }
    pos_ += static_cast<uint64_t>(found - begin);
    uint32_t size = 0;
    const char* ignored = nullptr;
    if (CheckRecord(&size, &ignored) == Check::kGood) break;
    ++pos_;
  }
  const uint64_t skipped = pos_ - start;
  ++damaged_stretches_;
  skipped_bytes_ += skipped;
  if (Available(1) == 0) {
    torn_tail_ = true;
    torn_tail_at_ = start;
    torn_tail_bytes_ = skipped;
    torn_tail_why_ = why;
  } else if (damaged_stretches_ == 1) {
    first_damage_at_ = start;
    first_damage_why_ = why;
  }
}

bool SessionLogReader::Next(LogRecord* record) {
  if (!file_) return false;
  while (Available(1) > 0) {
    uint32_t size = 0;
    const char* why = nullptr;
    if (CheckRecord(&size, &why) != Check::kGood) {
      Resynchronise(why);
      continue;
    }
    const uint8_t* header = buffer_.data() + (pos_ - buffer_offset_);
    record->receive_time_ns = GetU64(header + 8);
    record->payload.assign(header + kRecordHeader, header + kRecordHeader + size);
    pos_ += kRecordHeader + size;
    ++records_;
    return true;
  }
  std::fclose(file_);
  file_ = nullptr;
  buffer_.clear();
  buffer_.shrink_to_fit();
  return false;
}

std::string SessionLogReader::warning() const {
  std::string out;
  const uint64_t inside = damaged_stretches_ - (torn_tail_ ? 1 : 0);
  if (inside > 0) {
    out = "skipped " + std::to_string(inside) + " damaged stretch" + (inside == 1 ? "" : "es") + " (" +
          std::to_string(skipped_bytes_ - torn_tail_bytes_) + " bytes; the first at byte " +
          std::to_string(first_damage_at_) + ": " + first_damage_why_ + ") and resumed at the next good record";
  }
  if (torn_tail_) {
    out += (out.empty() ? "" : "; ") + std::string("the last ") + std::to_string(torn_tail_bytes_) +
           " bytes (from byte " + std::to_string(torn_tail_at_) + ") are no good record (" + torn_tail_why_ +
           "), as a crash during a write leaves them";
  }
  if (out.empty()) return out;
  return path_ + ": " + out + "; kept " + std::to_string(records_) + " good records";
}

}  // namespace mocap
