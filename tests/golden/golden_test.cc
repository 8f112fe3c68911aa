// Golden vectors, hub side, across the C/C++ boundary in both directions:
//  - committed bytes decode in C++ to exactly the committed text-format meaning;
//  - C++ encoding of that meaning reproduces the committed bytes;
//  - bytes the C firmware encodes decode identically in C++, and bytes C++ encodes decode in C
//    and re-encode to the same bytes;
//  - every reject vector is refused by the hub too.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <google/protobuf/text_format.h>
#include <google/protobuf/util/message_differencer.h>
#include <gtest/gtest.h>

#include "mocap.pb.h"
#include "vectors.h"
#include "wire/packet.h"
#include "wire/wire.h"

namespace {

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  EXPECT_TRUE(in.good()) << "cannot open " << path;
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

const std::string kDir = MOCAP_GOLDEN_DIR;

class Golden : public ::testing::TestWithParam<int> {};

TEST_P(Golden, CrossesTheBoundaryBothWays) {
  const std::string name = golden_vector_name(GetParam());
  const std::string bytes = ReadFile(kDir + "/" + name + ".bin");
  mocap::v1::Packet meaning;
  ASSERT_TRUE(google::protobuf::TextFormat::ParseFromString(ReadFile(kDir + "/" + name + ".txt"), &meaning));

  const auto decoded = mocap::wire::Decode(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
  ASSERT_TRUE(decoded.ok) << decoded.reason;
  EXPECT_TRUE(google::protobuf::util::MessageDifferencer::Equals(decoded.packet, meaning));

  const std::vector<uint8_t> cpp_bytes = mocap::wire::Encode(meaning);
  EXPECT_EQ(std::string(cpp_bytes.begin(), cpp_bytes.end()), bytes);

  static mocap_v1_Packet c_packet, c_back;
  uint8_t c_bytes[MN_WIRE_MAX_DATAGRAM];
  size_t c_size = 0;
  const char* reason = nullptr;
  golden_vector_build(GetParam(), &c_packet);
  ASSERT_EQ(mn_wire_encode(&c_packet, c_bytes, sizeof c_bytes, &c_size, &reason), 0) << reason;
  const auto from_c = mocap::wire::Decode(c_bytes, c_size);
  ASSERT_TRUE(from_c.ok) << from_c.reason;
  EXPECT_TRUE(google::protobuf::util::MessageDifferencer::Equals(from_c.packet, meaning));

  ASSERT_EQ(mn_wire_decode(cpp_bytes.data(), cpp_bytes.size(), &c_back, &reason), 0) << reason;
  uint8_t again[MN_WIRE_MAX_DATAGRAM];
  size_t again_size = 0;
  ASSERT_EQ(mn_wire_encode(&c_back, again, sizeof again, &again_size, &reason), 0) << reason;
  EXPECT_EQ(std::string(reinterpret_cast<char*>(again), again_size), bytes);
}

INSTANTIATE_TEST_SUITE_P(AllVectors, Golden, ::testing::Range(0, GOLDEN_VECTOR_COUNT),
                         [](const ::testing::TestParamInfo<int>& info) {
                           return std::string(golden_vector_name(info.param));
                         });

// Every reject/*.bin is a reject vector: a new file is tested without a code change.
TEST(GoldenReject, HubRefusesEveryRejectVector) {
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(kDir + "/reject"))
    if (entry.path().extension() == ".bin") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  ASSERT_FALSE(files.empty()) << "no reject vectors in " << kDir << "/reject";
  for (const auto& file : files) {
    const std::string name = file.stem().string();
    const std::string bytes = ReadFile(file.string());
    const auto r = mocap::wire::Decode(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
    EXPECT_FALSE(r.ok) << name;
    EXPECT_FALSE(r.reason.empty()) << name;
  }
}

}  // namespace
