// For tests that write files: a directory of the test's own, made empty by mkdtemp in the
// test's scratch directory (GoogleTest's TempDir(): TEST_TMPDIR, which cmake/Testing.cmake sets
// to build/test-tmp/<test program>, else /tmp), so tests running in parallel never share one and
// nothing a crashed run left behind is in it; removed with everything in it when the object goes
// out of scope, a failed ASSERT's early return included.
#pragma once

#include <stdlib.h>

#include <filesystem>
#include <stdexcept>
#include <string>
#include <system_error>

#include <gtest/gtest.h>

namespace mocap::testing {

class TemporaryDirectory {
 public:
  // `label` goes into the directory's name (mocap_<label>_XXXXXX), to tell whose it is.
  explicit TemporaryDirectory(const std::string& label) {
    std::string name = (std::filesystem::path(::testing::TempDir()) / ("mocap_" + label + "_XXXXXX")).string();
    if (::mkdtemp(name.data()) == nullptr) throw std::runtime_error("cannot make a temporary directory like " + name);
    path_ = name;
  }
  ~TemporaryDirectory() {
    // A test may have taken the owner's write permission away (to see a write refused); it is
    // given back first, or the removal would stop there.
    std::error_code ignored;
    std::filesystem::permissions(path_, std::filesystem::perms::owner_all, std::filesystem::perm_options::add, ignored);
    std::filesystem::remove_all(path_, ignored);
  }
  TemporaryDirectory(const TemporaryDirectory&) = delete;
  TemporaryDirectory& operator=(const TemporaryDirectory&) = delete;

  const std::filesystem::path& path() const { return path_; }
  // The path of `name` inside the directory (made by the caller, if at all).
  std::string File(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

}  // namespace mocap::testing
