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
#include "wire/datagram_envelope.h"
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

// The hub seals every golden envelope byte for byte as the firmware does (the C side checks the
// same bytes), opens the committed bytes under the golden key and decodes the packet inside.
TEST(GoldenEnvelope, HubSealsAndOpensTheFirmwaresBytes) {
  mocap::wire::InitSodium();
  mocap::wire::WireKey key;
  golden_envelope_key(key.data());
  for (int i = 0; i < GOLDEN_ENVELOPE_COUNT; ++i) {
    const golden_envelope* g = golden_envelope_at(i);
    const std::string bytes = ReadFile(kDir + "/" + g->name + ".bin");
    const std::string plain = ReadFile(kDir + "/" + golden_vector_name(g->packet_vector) + ".bin");
    const mocap::wire::EnvelopeHeader h{static_cast<mocap::wire::Direction>(g->direction), g->key_id, g->node_id,
                                        g->counter};
    const auto sealed = mocap::wire::SealEnvelope(h, key, reinterpret_cast<const uint8_t*>(plain.data()), plain.size());
    EXPECT_EQ(std::string(sealed.begin(), sealed.end()), bytes) << g->name;
    const auto* data = reinterpret_cast<const uint8_t*>(bytes.data());
    const mocap::wire::ParsedEnvelope p = mocap::wire::ParseEnvelope(data, bytes.size());
    ASSERT_TRUE(p.ok) << g->name << ": " << p.reason;
    EXPECT_TRUE(mocap::wire::VerifyEnvelopeTag(data, bytes.size(), key)) << g->name;
    EXPECT_EQ(p.header.counter, g->counter);
    EXPECT_EQ(p.header.node_id, g->node_id);
    EXPECT_EQ(std::string(reinterpret_cast<const char*>(p.payload), p.payload_size), plain);
    EXPECT_TRUE(mocap::wire::Decode(p.payload, p.payload_size).ok) << g->name;
  }
}

TEST(GoldenEnvelope, HubRefusesEveryRejectVector) {
  mocap::wire::WireKey key;
  golden_envelope_key(key.data());
  size_t count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(kDir + "/reject_envelope")) {
    if (entry.path().extension() != ".bin") continue;
    const std::string bytes = ReadFile(entry.path().string());
    const auto* data = reinterpret_cast<const uint8_t*>(bytes.data());
    const mocap::wire::ParsedEnvelope p = mocap::wire::ParseEnvelope(data, bytes.size());
    EXPECT_FALSE(p.ok && mocap::wire::VerifyEnvelopeTag(data, bytes.size(), key)) << entry.path();
    ++count;
  }
  EXPECT_GT(count, 0u);
}

}  // namespace
