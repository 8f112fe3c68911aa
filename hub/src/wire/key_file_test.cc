// Wire key files, hub side: the format the firmware reads, refusals naming the line, files
// written atomically with mode 0600 and refused when others may read them, and generated keys.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <string>

#include "util/special_file_testing.h"
#include "util/temporary_directory_testing.h"
#include "wire/key_file.h"

namespace mocap::wire {
namespace {

const std::string kHexA = "000102030405060708090a0b0c0d0e0f101112131415161718191a1b1c1d1e1f";
const std::string kHexB = "FFEEDDCCBBAA99887766554433221100ffeeddccbbaa99887766554433221100";

TEST(KeyFile, ParsesTheFirmwaresFormat) {
  const KeyFile f = ParseKeyFile("# key\nnode = 12\nkey = 2 " + kHexB + "  # next\n  key=1   " + kHexA + "\r\n\n", "k.key");
  EXPECT_EQ(f.node_id, 12u);
  ASSERT_EQ(f.keys.size(), 2u);
  EXPECT_EQ(f.keys[0].id, 2);
  EXPECT_EQ(f.keys[0].key[0], 0xff);
  EXPECT_EQ(f.keys[1].key[31], 0x1f);
  EXPECT_EQ(f.Find(1), &f.keys[1]);
  EXPECT_EQ(f.Find(3), nullptr);
  const KeyFile back = ParseKeyFile(FormatKeyFile(f), "again");
  EXPECT_EQ(back.node_id, 12u);
  EXPECT_EQ(back.keys[0].key, f.keys[0].key);
  EXPECT_EQ(back.keys[1].id, 1);
}

TEST(KeyFile, RefusalsNameTheLine) {
  const std::pair<std::string, std::string> bad[] = {
      {"", "k.key: no `node = ID` line"},
      {"node = 3\n", "k.key: no `key = ID HEX` line"},
      {"node = 3\nnode = 3\n", "k.key:2: node given twice"},
      {"node = 4096\n", "k.key:1: node must be 1..4095"},
      {"node = 3\nkey = 0 " + kHexA, "k.key:2: key must be `ID HEX`"},
      {"node = 3\nkey = 1 " + kHexA + "0", "k.key:2: key must be `ID HEX`"},
      {"node = 3\nkey = 1 " + kHexA + "\nkey = 1 " + kHexB, "k.key:3: key id 1 given twice"},
      {"node = 3\nkey = 1 " + kHexA + "\nkey = 2 " + kHexB + "\nkey = 3 " + kHexA, "k.key:4: more than 2 keys"},
      {"node = 3\nsecret = 1\n", "k.key:2: unknown key 'secret'"},
      {"node 3\n", "k.key:1: expected `key = value`"},
      {std::string(5000, '#'), "k.key: larger than 4096 bytes"},
  };
  for (const auto& [text, message] : bad) {
    try {
      ParseKeyFile(text, "k.key");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what() << " vs " << message;
    }
  }
}

TEST(KeyFile, WrittenPrivateAndRefusedWhenOthersMayRead) {
  const testing::TemporaryDirectory temp("key_file_test");
  const std::string path = temp.File(KeyFileName(5));
  EXPECT_EQ(KeyFileName(5), "node-5.key");
  KeyFile f;
  f.node_id = 5;
  f.keys.push_back({1, GenerateKey()});
  f.keys.push_back({2, GenerateKey()});
  EXPECT_NE(f.keys[0].key, f.keys[1].key);
  WriteKeyFile(path, f);
  struct stat st{};
  ASSERT_EQ(stat(path.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600u);
  const KeyFile back = ReadKeyFile(path);
  EXPECT_EQ(back.keys[1].key, f.keys[1].key);
  ASSERT_EQ(chmod(path.c_str(), 0640), 0);
  try {
    ReadKeyFile(path);
    ADD_FAILURE() << "a group-readable key file was read";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("mode 640 lets others read it"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ReadKeyFile(temp.File("none.key")), std::runtime_error);
}

// The key file is checked to be a regular file once opened; a FIFO's open waited for a writer
// before that check could run.
TEST(KeyFile, AFifoIsRefusedWithoutWaiting) {
  const auto read = [](const std::string& path) { ReadKeyFile(path); };
  const std::string error = mocap::testing::ErrorOfReadingAFifo(read, "node-5.key");
  EXPECT_NE(error.find("node-5.key: not a regular file"), std::string::npos) << error;
  EXPECT_NE(error.rfind("waited", 0), 0u) << error;
}

}  // namespace
}  // namespace mocap::wire
