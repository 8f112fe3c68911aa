// Config files: the format, the errors with file:line, flags winning, and the shipped example
// naming only real options of serve.
#include "cli/config_file.h"

#include <fstream>

#include <gtest/gtest.h>

#include "cli/commands.h"
#include "util/temporary_directory_testing.h"

namespace mocap {
namespace {

// Writes text to a file in dir; returns its path.
std::string WriteTemp(const testing::TemporaryDirectory& dir, const std::string& text) {
  const std::string path = dir.File("hub.conf");
  std::ofstream(path) << text;
  return path;
}

TEST(ConfigFile, KeysValuesCommentsAndQuotes) {
  const testing::TemporaryDirectory temp("config_file_test");
  const std::string path = WriteTemp(temp, "# comment\n\n  rate = 120 \nname = \"a b\"\nempty =\n");
  const std::vector<ConfigEntry> entries = ReadConfigFile(path);
  ASSERT_EQ(entries.size(), 3u);
  EXPECT_EQ(entries[0].line, 3);
  EXPECT_EQ(entries[0].key, "rate");
  EXPECT_EQ(entries[0].value, "120");
  EXPECT_EQ(entries[1].value, "a b");
  EXPECT_EQ(entries[2].value, "");
}

TEST(ConfigFile, ErrorsNameTheLine) {
  const testing::TemporaryDirectory temp("config_file_test");
  const std::string path = WriteTemp(temp, "rate = 1\nno equals sign\n");
  try {
    ReadConfigFile(path);
    FAIL() << "accepted a line without '='";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(":2:"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ReadConfigFile("/nonexistent/hub.conf"), std::runtime_error);
}

TEST(ConfigFile, CommandLineWinsAndUnknownKeysAreUsageErrors) {
  CLI::App app;
  CLI::App* command = app.add_subcommand("serve");
  double rate = 0;
  std::string listen;
  command->add_option("--rate", rate);
  command->add_option("--listen", listen);
  const testing::TemporaryDirectory temp("config_file_test");
  const std::string path = WriteTemp(temp, "rate = 120\nlisten = 1.2.3.4:5\n");
  app.parse("serve --listen 9.9.9.9:1", false);
  ApplyConfigFile(*command, path);
  EXPECT_EQ(rate, 120.0);
  EXPECT_EQ(listen, "9.9.9.9:1");
  std::ofstream(path) << "colour = red\n";
  EXPECT_THROW(ApplyConfigFile(*command, path), UsageError);
  CLI::App fresh;
  CLI::App* other = fresh.add_subcommand("serve");
  other->add_option("--rate", rate);
  std::ofstream(path) << "rate = fast\n";
  EXPECT_THROW(ApplyConfigFile(*other, path), UsageError);
}

// The file is read whole and bounded first: /dev/zero (an existing file to --config's check) made
// one line grow without end, and a long file without newlines was buffered whole.
TEST(ConfigFile, OnlyRegularFilesUpTo64KiBAreRead) {
  try {
    ReadConfigFile("/dev/zero");
    FAIL() << "read /dev/zero";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/dev/zero: not a regular file"), std::string::npos) << e.what();
  }
  const testing::TemporaryDirectory temp("config_file_test");
  const std::string path = WriteTemp(temp, std::string(64 * 1024 + 1, '#'));
  try {
    ReadConfigFile(path);
    FAIL() << "read a file over 64 KiB";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path + ": larger than 64 KiB"), std::string::npos) << e.what();
  }
  std::string comments;
  for (int i = 0; i < 1023; ++i) comments += std::string(63, '#') + "\n";
  std::ofstream(path) << comments << "rate = 1\n";  // 65481 bytes
  EXPECT_EQ(ReadConfigFile(path).size(), 1u);
}

// A key on two lines was applied from the first and the second dropped without a word (the
// option then counted as given); it is refused naming both lines.
TEST(ConfigFile, AKeyOnTwoLinesIsRefusedNamingBoth) {
  CLI::App app;
  CLI::App* command = app.add_subcommand("serve");
  double rate = 0;
  command->add_option("--rate", rate);
  const testing::TemporaryDirectory temp("config_file_test");
  const std::string path = WriteTemp(temp, "rate = 100\n# later\nrate = 200\n");
  try {
    ApplyConfigFile(*command, path);
    FAIL() << "applied a key given twice";
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find(":3: 'rate' is set already on line 1"), std::string::npos) << e.what();
  }
}

TEST(ConfigFile, TheShippedExampleNamesOnlyServeOptions) {
  CLI::App app;
  AddServeCommand(app);
  CLI::App* serve = app.get_subcommand("serve");
  const std::vector<ConfigEntry> entries = ReadConfigFile(MOCAP_HUB_CONF_EXAMPLE);
  EXPECT_GE(entries.size(), 5u);
  for (const ConfigEntry& e : entries) EXPECT_NE(serve->get_option_no_throw("--" + e.key), nullptr) << e.key;
}

}  // namespace
}  // namespace mocap
