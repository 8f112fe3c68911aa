// Append-only datagram log with per-record CRC (format in session_log.h).
#include "ingest/session_log.h"

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
      std::fwrite(data, 1, size, file_) != size)
    throw IoError("write failed", path_);
  ++records_;
}

void SessionLogWriter::Flush() {
  if (file_ && std::fflush(file_) != 0) throw IoError("flush failed", path_);
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
    throw std::runtime_error(path + ": unsupported session log version " + std::to_string(GetU32(header + 8)));
  offset_ = sizeof header;
}

bool SessionLogReader::Next(LogRecord* record) {
  if (!file_) return false;
  uint8_t header[kRecordHeader];
  const size_t got = std::fread(header, 1, sizeof header, file_);
  auto stop = [&](const std::string& why) {
    warning_ = path_ + ": " + why + " at byte " + std::to_string(offset_) + "; kept the " +
               std::to_string(records_) + " records before it";
    std::fclose(file_);
    file_ = nullptr;
    return false;
  };
  if (got == 0 && std::feof(file_)) {
    std::fclose(file_);
    file_ = nullptr;
    return false;
  }
  if (got != sizeof header) return stop("truncated record header");
  if (GetU32(header) != kRecordMagic) return stop("corrupt record (bad magic)");
  const uint32_t size = GetU32(header + 4);
  if (size > kMaxPayload) return stop("corrupt record (impossible length)");
  record->payload.resize(size);
  if (std::fread(record->payload.data(), 1, size, file_) != size) return stop("truncated record");
  if (RecordCrc(header + 8, record->payload.data(), size) != GetU32(header + 16))
    return stop("corrupt record (CRC mismatch)");
  record->receive_time_ns = GetU64(header + 8);
  offset_ += sizeof header + size;
  ++records_;
  return true;
}

}  // namespace mocap
