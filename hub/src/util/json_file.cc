#include "util/json_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "util/regular_file.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void Fail(const std::string& path, const std::string& what) {
  throw std::runtime_error(path + ": " + what);
}

std::string ErrnoText() { return std::strerror(errno); }

// Writes all of `text` to a new file and fsyncs it; removes the file on any failure.
void WriteSynced(const std::string& path, const std::string& text) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) Fail(path, "cannot create: " + ErrnoText());
  size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const std::string why = ErrnoText();
      ::close(fd);
      ::unlink(path.c_str());
      Fail(path, "write failed: " + why);
    }
    done += static_cast<size_t>(n);
  }
  if (::fsync(fd) != 0 || ::close(fd) != 0) {
    const std::string why = ErrnoText();
    ::unlink(path.c_str());
    Fail(path, "cannot flush to disk: " + why);
  }
}

void SyncDirectory(const fs::path& dir) {
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;  // the rename happened; an unsyncable directory only weakens crash safety
  ::fsync(fd);
  ::close(fd);
}

}  // namespace

nlohmann::json ReadJsonFile(const std::string& path) {
  const std::string text = ReadRegularFile(path, kMaxJsonFileBytes, "a JSON file");
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& error) {
    Fail(path, "not valid JSON at byte " + std::to_string(error.byte) + " (" + error.what() + ")");
  } catch (const nlohmann::json::exception& error) {
    // The parser throws out_of_range for a number no double holds (1e500), not parse_error.
    Fail(path, std::string("not valid JSON (") + error.what() + ")");
  }
}

void WriteJsonFile(const nlohmann::json& document, const std::string& path, int indent) {
  std::string text;
  try {
    text = document.dump(indent) + "\n";
  } catch (const nlohmann::json::exception& error) {
    Fail(path, std::string("cannot serialise: ") + error.what());
  }
  WriteTextFile(text, path);
}

void WriteTextFile(const std::string& text, const std::string& path) {
  const fs::path target(path);
  const fs::path parent = target.parent_path();
  std::error_code ec;
  if (!parent.empty()) fs::create_directories(parent, ec);
  if (ec) Fail(path, "cannot create directory " + parent.string() + ": " + ec.message());
  const std::string temporary = path + ".tmp";
  WriteSynced(temporary, text);
  if (::rename(temporary.c_str(), path.c_str()) != 0) {
    const std::string why = ErrnoText();
    ::unlink(temporary.c_str());
    Fail(path, "cannot replace: " + why);
  }
  SyncDirectory(parent);
}

}  // namespace mocap
