// Wire key files (see key_file.h).
#include "wire/key_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <algorithm>
#include <cstring>
#include <stdexcept>

#include <sodium.h>

namespace mocap::wire {
namespace {

std::string Trim(const std::string& s) {
  const size_t first = s.find_first_not_of(" \t\r");
  if (first == std::string::npos) return "";
  return s.substr(first, s.find_last_not_of(" \t\r") - first + 1);
}

bool ParseUint(const std::string& s, unsigned long lo, unsigned long hi, unsigned long* out) {
  if (s.empty() || s.size() > 10) return false;
  unsigned long v = 0;
  for (char c : s) {
    if (c < '0' || c > '9') return false;
    v = v * 10 + static_cast<unsigned long>(c - '0');
  }
  if (v < lo || v > hi) return false;
  *out = v;
  return true;
}

int HexValue(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

bool ParseKey(const std::string& value, WireKeyEntry* entry) {
  const size_t space = value.find_first_of(" \t");
  if (space == std::string::npos) return false;
  unsigned long id = 0;
  if (!ParseUint(value.substr(0, space), 1, 255, &id)) return false;
  const std::string hex = Trim(value.substr(space));
  if (hex.size() != 2 * kWireKeyBytes) return false;
  for (size_t b = 0; b < kWireKeyBytes; ++b) {
    const int hi = HexValue(hex[2 * b]), lo = HexValue(hex[2 * b + 1]);
    if (hi < 0 || lo < 0) return false;
    entry->key[b] = static_cast<uint8_t>(hi << 4 | lo);
  }
  entry->id = static_cast<uint8_t>(id);
  return true;
}

}  // namespace

const WireKeyEntry* KeyFile::Find(uint8_t id) const {
  for (const WireKeyEntry& k : keys)
    if (k.id == id) return &k;
  return nullptr;
}

KeyFile ParseKeyFile(const std::string& text, const std::string& origin) {
  if (text.size() > kMaxKeyFileBytes)
    throw std::invalid_argument(origin + ": larger than " + std::to_string(kMaxKeyFileBytes) + " bytes");
  KeyFile file;
  size_t pos = 0;
  for (int line = 1; pos < text.size(); ++line) {
    const size_t end = std::min(text.find('\n', pos), text.size());
    std::string s = text.substr(pos, end - pos);
    pos = end + 1;
    const auto where = [&] { return origin + ":" + std::to_string(line) + ": "; };
    const size_t cut = s.find_first_of(std::string("#\0", 2));
    if (cut != std::string::npos) s.resize(cut);
    s = Trim(s);
    if (s.empty()) continue;
    const size_t eq = s.find('=');
    if (eq == std::string::npos) throw std::invalid_argument(where() + "expected `key = value`");
    const std::string key = Trim(s.substr(0, eq)), value = Trim(s.substr(eq + 1));
    if (key == "node") {
      unsigned long id = 0;
      if (file.node_id != 0) throw std::invalid_argument(where() + "node given twice");
      if (!ParseUint(value, 1, 4095, &id)) throw std::invalid_argument(where() + "node must be 1..4095");
      file.node_id = static_cast<uint32_t>(id);
    } else if (key == "key") {
      WireKeyEntry entry;
      if (file.keys.size() == kMaxKeysPerFile)
        throw std::invalid_argument(where() + "more than " + std::to_string(kMaxKeysPerFile) + " keys");
      if (!ParseKey(value, &entry))
        throw std::invalid_argument(where() + "key must be `ID HEX` (id 1..255, 64 hex digits)");
      if (file.Find(entry.id))
        throw std::invalid_argument(where() + "key id " + std::to_string(entry.id) + " given twice");
      file.keys.push_back(entry);
    } else {
      throw std::invalid_argument(where() + "unknown key '" + key + "'");
    }
  }
  if (file.node_id == 0) throw std::invalid_argument(origin + ": no `node = ID` line");
  if (file.keys.empty()) throw std::invalid_argument(origin + ": no `key = ID HEX` line");
  return file;
}

std::string FormatKeyFile(const KeyFile& file) {
  std::string text = "# mocap wire key (HMAC-SHA-512/256) of node " + std::to_string(file.node_id) +
                     ". Secret: mode 0600, never in a repository.\n# The first key signs; every key listed is "
                     "accepted (two during a change-over).\nnode = " +
                     std::to_string(file.node_id) + "\n";
  for (const WireKeyEntry& k : file.keys) {
    text += "key = " + std::to_string(k.id) + " ";
    char hex[3];
    for (uint8_t b : k.key) {
      std::snprintf(hex, sizeof hex, "%02x", b);
      text += hex;
    }
    text += "\n";
  }
  return text;
}

KeyFile ReadKeyFile(const std::string& path) {
  // O_NONBLOCK: a FIFO's open would wait for a writer before the regular-file check below.
  const int fd = open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOCTTY | O_NONBLOCK);
  if (fd < 0) throw std::runtime_error("key file " + path + ": " + std::strerror(errno));
  struct stat st{};
  if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    close(fd);
    throw std::runtime_error("key file " + path + ": not a regular file");
  }
  if (st.st_mode & (S_IRWXG | S_IRWXO)) {
    close(fd);
    char mode[8];
    std::snprintf(mode, sizeof mode, "%03o", static_cast<unsigned>(st.st_mode & 0777));
    throw std::runtime_error("key file " + path + ": mode " + mode + " lets others read it; chmod 600 it");
  }
  std::string text(kMaxKeyFileBytes + 1, '\0');
  size_t size = 0;
  while (size < text.size()) {
    const ssize_t n = read(fd, text.data() + size, text.size() - size);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const int e = errno;
      close(fd);
      throw std::runtime_error("key file " + path + ": " + std::strerror(e));
    }
    if (n == 0) break;
    size += static_cast<size_t>(n);
  }
  close(fd);
  text.resize(size);
  try {
    KeyFile file = ParseKeyFile(text, path);
    sodium_memzero(text.data(), text.size());
    return file;
  } catch (const std::invalid_argument& e) {
    sodium_memzero(text.data(), text.size());
    throw std::runtime_error(e.what());
  }
}

void WriteKeyFile(const std::string& path, const KeyFile& file) {
  const std::string text = FormatKeyFile(file);
  const std::string tmp = path + ".tmp";
  const int fd = open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC | O_NOFOLLOW, 0600);
  if (fd < 0) throw std::runtime_error("key file " + tmp + ": " + std::strerror(errno));
  bool ok = fchmod(fd, 0600) == 0 && write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size()) &&
            fsync(fd) == 0;
  const int e = errno;
  ok = close(fd) == 0 && ok;
  if (!ok || rename(tmp.c_str(), path.c_str()) != 0) {
    const int why = ok ? errno : e;
    unlink(tmp.c_str());
    throw std::runtime_error("key file " + path + ": cannot write: " + std::strerror(why));
  }
}

WireKey GenerateKey() {
  InitSodium();
  WireKey key;
  randombytes_buf(key.data(), key.size());
  return key;
}

std::string KeyFileName(uint32_t node_id) { return "node-" + std::to_string(node_id) + ".key"; }

}  // namespace mocap::wire
