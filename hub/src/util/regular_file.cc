#include "util/regular_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <algorithm>
#include <cstring>
#include <stdexcept>

namespace mocap {
namespace {

[[noreturn]] void Fail(const std::string& path, const std::string& what) {
  throw std::runtime_error(path + ": " + what);
}

const char* TypeText(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a file";
}

// Closes the descriptor on every way out, the throwing ones included.
class Descriptor {
 public:
  explicit Descriptor(int fd) : fd_(fd) {}
  ~Descriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  Descriptor(const Descriptor&) = delete;
  Descriptor& operator=(const Descriptor&) = delete;
  int get() const { return fd_; }

 private:
  int fd_;
};

}  // namespace

std::string ByteSizeText(size_t bytes) {
  static const struct {
    size_t unit;
    const char* name;
  } kUnits[] = {{size_t{1} << 30, " GiB"}, {size_t{1} << 20, " MiB"}, {size_t{1} << 10, " KiB"}};
  for (const auto& u : kUnits) {
    if (bytes >= u.unit && bytes % u.unit == 0) return std::to_string(bytes / u.unit) + u.name;
  }
  return std::to_string(bytes) + " bytes";
}

std::string ReadRegularFile(const std::string& path, size_t max_bytes, const std::string& kind) {
  const std::string bound = ByteSizeText(max_bytes);
  // O_NONBLOCK: opening a FIFO for reading otherwise waits for a writer, before any check could
  // run. It changes nothing for a regular file's reads.
  const Descriptor fd(::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOCTTY | O_NONBLOCK));
  if (fd.get() < 0) Fail(path, std::string("cannot open: ") + std::strerror(errno));
  struct stat st {};
  if (::fstat(fd.get(), &st) != 0) Fail(path, std::string("cannot open: ") + std::strerror(errno));
  if (!S_ISREG(st.st_mode))
    Fail(path, std::string("not a regular file (") + TypeText(st.st_mode) + "); " + kind +
                   " is a regular file of at most " + bound);
  const auto too_large = [&] { Fail(path, "larger than " + bound + ", the bound for " + kind); };
  if (static_cast<unsigned long long>(st.st_size) > max_bytes) too_large();
  // Read to the end rather than to st_size: a file may grow or shrink after the stat; one byte
  // past the bound shows it is over.
  std::string bytes(static_cast<size_t>(st.st_size) + 1, '\0');
  size_t size = 0;
  for (;;) {
    if (size == bytes.size()) {
      if (size > max_bytes) too_large();
      bytes.resize(std::min(max_bytes + 1, std::max<size_t>(2 * size, 4096)));
    }
    const ssize_t n = ::read(fd.get(), &bytes[size], bytes.size() - size);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) Fail(path, std::string("read failed: ") + std::strerror(errno));
    if (n == 0) break;
    size += static_cast<size_t>(n);
  }
  if (size > max_bytes) too_large();
  bytes.resize(size);
  return bytes;
}

}  // namespace mocap
