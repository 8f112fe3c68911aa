// Who may ask serve's API what: tokens with a role. A token is 32 bytes from libsodium's CSPRNG,
// given to its holder as 64 hex digits in a file of its own (mode 0600, `mocap-hub tokens new`);
// serve keeps only its BLAKE2b hash in the token store, one line per token:
//     NAME ROLE HASH          e.g.  local operator 3f2a...(64 hex digits)
// so a copy of the store grants nothing. Roles: viewer (reads: GET and HEAD, the WebSockets) and
// operator (everything: control, captures, calibration apply). Rotation is issuing the same name
// again (the old token stops working as soon as serve re-reads the store, within a second);
// revoking removes the line. Error policy: parsers throw std::invalid_argument naming
// origin:line, file functions std::runtime_error naming the path.
#pragma once

#include <array>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace mocap::api {

enum class ApiRole { kViewer, kOperator };
const char* RoleName(ApiRole role);
std::optional<ApiRole> ParseRole(const std::string& text);

struct ApiPrincipal {
  std::string name;
  ApiRole role = ApiRole::kViewer;
};

using TokenHash = std::array<uint8_t, 32>;

struct TokenEntry {
  std::string name;  // letters, digits, '.', '-', '_'; 1-64 characters
  ApiRole role = ApiRole::kViewer;
  TokenHash hash{};
};

constexpr size_t kMaxTokens = 256;
constexpr size_t kMaxTokenStoreBytes = 64 * 1024;

bool ValidTokenName(const std::string& name);
std::vector<TokenEntry> ParseTokenStore(const std::string& text, const std::string& origin);
std::string FormatTokenStore(const std::vector<TokenEntry>& entries);
// A missing store reads as empty; a store group or others may read is refused (as key files).
std::vector<TokenEntry> ReadTokenStore(const std::string& path);
void WriteTokenStore(const std::string& path, const std::vector<TokenEntry>& entries);

// 64 hex digits from 32 random bytes.
std::string GenerateToken();
// BLAKE2b-256 of the token's text.
TokenHash HashToken(const std::string& token);
// A holder's token file: the token and a line end, mode 0600, written atomically.
void WriteTokenFile(const std::string& path, const std::string& token);
// The token in a holder's file (surrounding white space ignored); throws naming the path when
// it is not 64 hex digits.
std::string ReadTokenFile(const std::string& path);

// Issues NAME with ROLE (a new name, or a rotation of an existing one): the store gets the new
// hash, `token_file` the token. Returns the token.
std::string IssueToken(const std::string& store, const std::string& name, ApiRole role, const std::string& token_file);
// Removes NAME from the store; false when there was none.
bool RevokeToken(const std::string& store, const std::string& name);

// The store as serve uses it: thread-safe, re-read when its file changes (looked at most once a
// second); a store that cannot be read keeps the previous tokens and says so once.
class TokenVerifier {
 public:
  explicit TokenVerifier(std::string store_path);
  // The token's holder, or nothing. Constant time in the token's content.
  std::optional<ApiPrincipal> Verify(const std::string& token, uint64_t now_ns);
  size_t size();

 private:
  void ReloadIfChanged(uint64_t now_ns);

  std::string path_;
  std::mutex mutex_;
  std::vector<TokenEntry> entries_;
  std::string fingerprint_;
  uint64_t next_check_ns_ = 0;
};

}  // namespace mocap::api
