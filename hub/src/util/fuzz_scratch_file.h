// For fuzzers of readers that take a path: a file of this fuzzer process that holds each input in
// turn (in the temporary directory, named by the process id so that parallel runs never share
// it), removed when the process exits.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace mocap {

class FuzzScratchFile {
 public:
  explicit FuzzScratchFile(const std::string& name)
      : path_((std::filesystem::temp_directory_path() / ("mocap_fuzz_" + std::to_string(::getpid()) + "_" + name))
                  .string()) {}
  ~FuzzScratchFile() {
    std::error_code ignored;
    std::filesystem::remove(path_, ignored);
  }
  FuzzScratchFile(const FuzzScratchFile&) = delete;
  FuzzScratchFile& operator=(const FuzzScratchFile&) = delete;

  // Replaces the file's content with the input; returns its path.
  const std::string& Write(const uint8_t* data, size_t size) const {
    std::ofstream out(path_, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    return path_;
  }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

}  // namespace mocap
