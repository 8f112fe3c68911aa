// The console's static files: what is served, with which type, and that no path (dot segments,
// hidden files, links out of the mount, unknown types) reaches anything else.
#include "api/static_files.h"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "util/temporary_directory_testing.h"

namespace mocap::api {
namespace {
namespace fs = std::filesystem;

class StaticFilesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::create_directories(dir_ / "web" / "js");
    fs::create_directories(dir_ / "three" / "build");
    std::ofstream(dir_ / "web" / "index.html") << "<html>";
    std::ofstream(dir_ / "web" / "js" / "main.js") << "export {}";
    std::ofstream(dir_ / "web" / "js" / ".hidden.js") << "x";
    std::ofstream(dir_ / "web" / "notes.txt") << "x";
    std::ofstream(dir_ / "secret.js") << "x";
    fs::create_symlink(dir_ / "secret.js", dir_ / "web" / "js" / "out.js");
    std::ofstream(dir_ / "three" / "three.module.js") << "x";
    fs::create_symlink("../three.module.js", dir_ / "three" / "build" / "three.module.js");
    mounts_ = ConsoleMounts((dir_ / "web").string(), (dir_ / "three").string());
  }
  const testing::TemporaryDirectory temp_{"static_files_test"};
  const fs::path dir_ = temp_.path();
  std::vector<StaticMount> mounts_;
};

TEST_F(StaticFilesTest, ServesTheConsoleAndThreeJs) {
  ASSERT_EQ(mounts_.size(), 2u);
  const StaticFile index = ResolveStaticFile(mounts_, "/");
  ASSERT_EQ(index.status, 200) << index.reason;
  EXPECT_EQ(fs::path(index.path), fs::canonical(dir_ / "web" / "index.html"));
  EXPECT_EQ(index.content_type, "text/html; charset=utf-8");
  const StaticFile js = ResolveStaticFile(mounts_, "/js/main.js");
  ASSERT_EQ(js.status, 200);
  EXPECT_EQ(js.content_type, "text/javascript; charset=utf-8");  // ES modules need a JS type
  // A link inside the mount (Debian's build/three.module.js) is followed.
  const StaticFile three = ResolveStaticFile(mounts_, "/vendor/three/build/three.module.js");
  ASSERT_EQ(three.status, 200) << three.reason;
  EXPECT_EQ(fs::path(three.path), fs::canonical(dir_ / "three" / "three.module.js"));
}

TEST_F(StaticFilesTest, NothingElseIsReachable) {
  for (const char* path : {"", "index.html", "/../secret.js", "/js/../../secret.js", "/js/..", "/js/.hidden.js",
                           "/js/out.js", "/notes.txt", "/js", "/js/", "//index.html", "/js//main.js",
                           "/vendor/three/../web/index.html", "/vendor/three/", "/missing.js", "/js/main.js\\x00",
                           "/js/ma in.js", "/js/main.js?x=1", "/js\\\\main.js"}) {
    const StaticFile f = ResolveStaticFile(mounts_, path);
    EXPECT_EQ(f.status, 404) << path;
    EXPECT_FALSE(f.reason.empty()) << path;
    EXPECT_TRUE(f.path.empty()) << path;
  }
  EXPECT_EQ(ResolveStaticFile(mounts_, "/" + std::string(600, 'a') + ".js").status, 404);
}

TEST_F(StaticFilesTest, MissingDirectoriesAreNoMounts) {
  EXPECT_TRUE(ConsoleMounts((dir_ / "nope").string(), "").empty());
  EXPECT_EQ(ResolveStaticFile({}, "/").status, 404);
}

TEST(ConsoleFiles, TheSourceTreesConsoleResolves) {
  const std::vector<StaticMount> mounts = ConsoleMounts(MOCAP_WEB_SOURCE_DIR, "");
  for (const char* path : {"/", "/js/main.js", "/css/console.css"})
    EXPECT_EQ(ResolveStaticFile(mounts, path).status, 200) << path;
}

}  // namespace
}  // namespace mocap::api
