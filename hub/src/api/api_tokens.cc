// The API's tokens (see api_tokens.h).
#include "api/api_tokens.h"

#include <fcntl.h>
#include <sodium.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "util/log.h"

namespace mocap::api {
namespace {

constexpr char kHex[] = "0123456789abcdef";

std::string Hex(const uint8_t* data, size_t size) {
  std::string out;
  for (size_t i = 0; i < size; ++i) {
    out += kHex[data[i] >> 4];
    out += kHex[data[i] & 15];
  }
  return out;
}

bool FromHex(const std::string& text, uint8_t* out, size_t size) {
  if (text.size() != 2 * size) return false;
  for (size_t i = 0; i < size; ++i) {
    int v[2];
    for (int k = 0; k < 2; ++k) {
      const char c = text[2 * i + static_cast<size_t>(k)];
      v[k] = c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10 : -1;
      if (v[k] < 0) return false;
    }
    out[i] = static_cast<uint8_t>(v[0] << 4 | v[1]);
  }
  return true;
}

void InitSodium() {
  if (sodium_init() < 0) throw std::runtime_error("libsodium cannot be initialised");
}

// Mode 0600, temporary file + fsync + rename: a reader sees the old file or the new one.
// Whose a file written by root becomes: the owner of the file it replaces, else of the directory
// it goes into. So `sudo mocap-hub tokens new` leaves the installed service's store its user's
// (serve could not read a store root took over) and a holder's file in a home its holder's.
bool OwnerFor(const std::string& path, uid_t* uid, gid_t* gid) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    const size_t slash = path.find_last_of('/');
    const std::string dir = slash == std::string::npos ? "." : slash == 0 ? "/" : path.substr(0, slash);
    if (::stat(dir.c_str(), &st) != 0) return false;
  }
  *uid = st.st_uid;
  *gid = st.st_gid;
  return true;
}

void WritePrivateFile(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  uid_t uid = 0;
  gid_t gid = 0;
  const bool chown_it = ::geteuid() == 0 && OwnerFor(path, &uid, &gid) && uid != 0;
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC | O_NOFOLLOW, 0600);
  if (fd < 0) throw std::runtime_error(tmp + ": cannot create: " + std::strerror(errno));
  bool ok = ::fchmod(fd, 0600) == 0 && (!chown_it || ::fchown(fd, uid, gid) == 0) &&
            ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size()) && ::fsync(fd) == 0;
  const int error = errno;
  ok = ::close(fd) == 0 && ok;
  if (!ok || ::rename(tmp.c_str(), path.c_str()) != 0) {
    const int why = ok ? errno : error;
    ::unlink(tmp.c_str());
    throw std::runtime_error(path + ": cannot write: " + std::strerror(why));
  }
}

// The whole file, refused when group or others may read it (a secret left open is a leak to fix
// before it is used) or when it is larger than `limit`.
std::string ReadPrivateFile(const std::string& path, size_t limit, const char* what) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw std::runtime_error(path + ": cannot open: " + std::strerror(errno));
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    throw std::runtime_error(path + ": not a regular file");
  }
  if (st.st_mode & 077) {
    ::close(fd);
    char mode[8];
    std::snprintf(mode, sizeof mode, "%03o", static_cast<unsigned>(st.st_mode & 0777));
    throw std::runtime_error(path + ": " + what + " readable by group or others (mode " + mode + "); chmod 600 it");
  }
  std::string text(std::min<size_t>(static_cast<size_t>(st.st_size), limit + 1), '\0');
  const ssize_t got = ::read(fd, text.data(), text.size());
  ::close(fd);
  if (got < 0) throw std::runtime_error(path + ": read failed: " + std::strerror(errno));
  text.resize(static_cast<size_t>(got));
  if (text.size() > limit) throw std::runtime_error(path + ": larger than " + std::to_string(limit) + " bytes");
  return text;
}

std::string Fingerprint(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return "absent";
  return std::to_string(st.st_ino) + ":" + std::to_string(st.st_size) + ":" + std::to_string(st.st_mtim.tv_sec) +
         "." + std::to_string(st.st_mtim.tv_nsec);
}

}  // namespace

const char* RoleName(ApiRole role) { return role == ApiRole::kOperator ? "operator" : "viewer"; }

std::optional<ApiRole> ParseRole(const std::string& text) {
  if (text == "viewer") return ApiRole::kViewer;
  if (text == "operator") return ApiRole::kOperator;
  return std::nullopt;
}

bool ValidTokenName(const std::string& name) {
  if (name.empty() || name.size() > 64) return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' || c == '-' ||
           c == '_';
  });
}

std::vector<TokenEntry> ParseTokenStore(const std::string& text, const std::string& origin) {
  std::vector<TokenEntry> entries;
  std::istringstream in(text);
  size_t number = 0;
  for (std::string line; std::getline(in, line);) {
    ++number;
    const auto fail = [&](const std::string& reason) {
      throw std::invalid_argument(origin + ":" + std::to_string(number) + ": " + reason);
    };
    const size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream fields(line);
    std::string name, role, hash, extra;
    fields >> name >> role >> hash;
    if (hash.empty() || (fields >> extra)) fail("expected NAME ROLE HASH");
    if (!ValidTokenName(name)) fail("token name '" + name + "': use 1-64 letters, digits, '.', '-' or '_'");
    TokenEntry entry;
    entry.name = name;
    const std::optional<ApiRole> parsed = ParseRole(role);
    if (!parsed) fail("role '" + role + "': viewer or operator");
    entry.role = *parsed;
    if (!FromHex(hash, entry.hash.data(), entry.hash.size())) fail("hash: 64 lower-case hex digits expected");
    for (const TokenEntry& e : entries)
      if (e.name == name) fail("token name '" + name + "' appears twice");
    if (entries.size() >= kMaxTokens) fail("more than " + std::to_string(kMaxTokens) + " tokens");
    entries.push_back(entry);
  }
  return entries;
}

std::string FormatTokenStore(const std::vector<TokenEntry>& entries) {
  std::string out = "# mocap-hub API tokens (`mocap-hub tokens`): NAME ROLE BLAKE2b-256(token)\n";
  for (const TokenEntry& e : entries)
    out += e.name + " " + RoleName(e.role) + " " + Hex(e.hash.data(), e.hash.size()) + "\n";
  return out;
}

std::vector<TokenEntry> ReadTokenStore(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 && errno == ENOENT) return {};
  try {
    return ParseTokenStore(ReadPrivateFile(path, kMaxTokenStoreBytes, "token store"), path);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(e.what());
  }
}

void WriteTokenStore(const std::string& path, const std::vector<TokenEntry>& entries) {
  WritePrivateFile(path, FormatTokenStore(entries));
}

std::string GenerateToken() {
  InitSodium();
  uint8_t bytes[32];
  randombytes_buf(bytes, sizeof bytes);
  return Hex(bytes, sizeof bytes);
}

TokenHash HashToken(const std::string& token) {
  InitSodium();
  TokenHash hash{};
  crypto_generichash(hash.data(), hash.size(), reinterpret_cast<const unsigned char*>(token.data()), token.size(),
                     nullptr, 0);
  return hash;
}

void WriteTokenFile(const std::string& path, const std::string& token) { WritePrivateFile(path, token + "\n"); }

std::string ReadTokenFile(const std::string& path) {
  std::string text = ReadPrivateFile(path, 1024, "token file");
  const size_t begin = text.find_first_not_of(" \t\r\n");
  const size_t end = text.find_last_not_of(" \t\r\n");
  text = begin == std::string::npos ? "" : text.substr(begin, end - begin + 1);
  uint8_t bytes[32];
  if (!FromHex(text, bytes, sizeof bytes)) throw std::runtime_error(path + ": not a token (64 hex digits)");
  return text;
}

std::string IssueToken(const std::string& store, const std::string& name, ApiRole role,
                       const std::string& token_file) {
  if (!ValidTokenName(name))
    throw std::invalid_argument("token name '" + name + "': use 1-64 letters, digits, '.', '-' or '_'");
  std::vector<TokenEntry> entries = ReadTokenStore(store);
  const std::string token = GenerateToken();
  auto it = std::find_if(entries.begin(), entries.end(), [&](const TokenEntry& e) { return e.name == name; });
  if (it == entries.end()) {
    if (entries.size() >= kMaxTokens) throw std::runtime_error(store + ": holds " + std::to_string(kMaxTokens) + " tokens already");
    it = entries.insert(entries.end(), TokenEntry{name, role, {}});
  }
  it->role = role;
  it->hash = HashToken(token);
  // The holder's file first: a store naming a token nobody holds is harmless, the reverse is not.
  WriteTokenFile(token_file, token);
  WriteTokenStore(store, entries);
  return token;
}

bool RevokeToken(const std::string& store, const std::string& name) {
  std::vector<TokenEntry> entries = ReadTokenStore(store);
  const auto it = std::remove_if(entries.begin(), entries.end(), [&](const TokenEntry& e) { return e.name == name; });
  if (it == entries.end()) return false;
  entries.erase(it, entries.end());
  WriteTokenStore(store, entries);
  return true;
}

TokenVerifier::TokenVerifier(std::string store_path) : path_(std::move(store_path)) {
  entries_ = ReadTokenStore(path_);
  fingerprint_ = Fingerprint(path_);
}

void TokenVerifier::ReloadIfChanged(uint64_t now_ns) {
  if (now_ns < next_check_ns_) return;
  next_check_ns_ = now_ns + 1'000'000'000ull;
  const std::string print = Fingerprint(path_);
  if (print == fingerprint_) return;
  fingerprint_ = print;
  try {
    entries_ = ReadTokenStore(path_);
    log::Info("{}: {} API tokens", path_, entries_.size());
  } catch (const std::exception& e) {
    log::Error("API tokens not reloaded, the previous ones stay in use: {}", e.what());
  }
}

std::optional<ApiPrincipal> TokenVerifier::Verify(const std::string& token, uint64_t now_ns) {
  const TokenHash hash = HashToken(token);
  std::lock_guard<std::mutex> lock(mutex_);
  ReloadIfChanged(now_ns);
  std::optional<ApiPrincipal> found;
  for (const TokenEntry& e : entries_)
    if (sodium_memcmp(e.hash.data(), hash.data(), hash.size()) == 0) found = ApiPrincipal{e.name, e.role};
  return found;
}

size_t TokenVerifier::size() {
  std::lock_guard<std::mutex> lock(mutex_);
  return entries_.size();
}

}  // namespace mocap::api
