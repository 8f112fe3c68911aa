// For tests of readers that take a path: what a reader makes of a FIFO (and of any path). A FIFO
// is the case to be careful with: a reader that opens it blocking waits for a writer, and one that
// then reads it waits for the writer to close. Should the reader still be at it after a few
// seconds, the test opens the FIFO for writing and closes it again (so the open returns and the
// read ends): the wait is reported as a failure instead of hanging the test.
#pragma once

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <functional>
#include <future>
#include <stdexcept>
#include <string>

#include "util/temporary_directory_testing.h"

namespace mocap::testing {

// The reader's std::runtime_error text, "" when it returned without one.
inline std::string ErrorOfReading(const std::function<void(const std::string&)>& read, const std::string& path) {
  try {
    read(path);
  } catch (const std::runtime_error& error) {
    return error.what();
  }
  return "";
}

// The error the reader gave for a FIFO of that name in a fresh temporary directory, or a text
// beginning "waited" if it did not give one within `patience`.
inline std::string ErrorOfReadingAFifo(const std::function<void(const std::string&)>& read, const std::string& name,
                                       std::chrono::seconds patience = std::chrono::seconds(5)) {
  const TemporaryDirectory dir("fifo_test");
  const std::string path = dir.File(name);
  if (::mkfifo(path.c_str(), 0600) != 0) throw std::runtime_error("cannot make the FIFO " + path);
  std::future<std::string> error = std::async(std::launch::async, [&] { return ErrorOfReading(read, path); });
  if (error.wait_for(patience) == std::future_status::ready) return error.get();
  // The reader waits in open (which a writer's open releases: O_NONBLOCK succeeds as a reader is
  // there) or, had it opened another way, in a read (which the last writer's close ends).
  int writer = ::open(path.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC);
  if (writer < 0) writer = ::open(path.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (writer >= 0) ::close(writer);
  return "waited on the FIFO for " + std::to_string(patience.count()) + " s (then: " + error.get() + ")";
}

}  // namespace mocap::testing
