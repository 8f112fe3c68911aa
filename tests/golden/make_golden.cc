// Writes the golden wire vectors: NAME.bin as the firmware (nanopb) encodes them, NAME.txt as
// the hub (libprotobuf) reads them, and reject/*.bin datagrams that both sides must refuse.
// Run by hand when the protocol changes: make_golden DIR. The tests never regenerate.
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include <google/protobuf/text_format.h>

#include "mocap.pb.h"
#include "vectors.h"
#include "wire/envelope.h"
#include "wire/packet.h"
#include "wire/wire.h"

namespace {

void WriteFile(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw std::runtime_error("cannot write " + path);
}

std::string Serialize(const mocap::v1::Packet& p) { return p.SerializeAsString(); }

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: make_golden DIR\n";
    return 2;
  }
  const std::string dir = argv[1];
  static mocap_v1_Packet packet;
  uint8_t buf[MN_WIRE_MAX_DATAGRAM];
  for (int i = 0; i < GOLDEN_VECTOR_COUNT; ++i) {
    golden_vector_build(i, &packet);
    size_t size = 0;
    const char* reason = nullptr;
    if (mn_wire_encode(&packet, buf, sizeof buf, &size, &reason) != 0) {
      std::cerr << golden_vector_name(i) << ": " << reason << "\n";
      return 1;
    }
    const auto decoded = mocap::wire::Decode(buf, size);
    if (!decoded.ok) {
      std::cerr << golden_vector_name(i) << ": hub rejects it: " << decoded.reason << "\n";
      return 1;
    }
    std::string text;
    google::protobuf::TextFormat::PrintToString(decoded.packet, &text);
    WriteFile(dir + "/" + golden_vector_name(i) + ".bin", std::string(reinterpret_cast<char*>(buf), size));
    WriteFile(dir + "/" + golden_vector_name(i) + ".txt", text);
  }

  // Datagrams both decoders must refuse, each breaking one rule.
  golden_vector_build(0, &packet);
  size_t size = 0;
  mn_wire_encode(&packet, buf, sizeof buf, &size, nullptr);
  mocap::v1::Packet base;
  base.ParseFromArray(buf, static_cast<int>(size));
  const std::string good = Serialize(base);

  mocap::v1::Packet p = base;
  p.set_version(2);
  WriteFile(dir + "/reject/wrong_version.bin", Serialize(p));
  WriteFile(dir + "/reject/truncated.bin", good.substr(0, good.size() - 3));
  WriteFile(dir + "/reject/oversized.bin", good + std::string(1401 - good.size(), '\0'));
  WriteFile(dir + "/reject/garbage.bin", std::string("\xff\xff\xff\xff\x0f\x08\x01", 7));
  p = base;
  p.mutable_marker_frame()->set_chunk_count(2);
  WriteFile(dir + "/reject/chunk_count_mismatch.bin", Serialize(p));
  p = base;
  p.mutable_marker_frame()->mutable_markers(1)->set_y_q8(800 * 256);
  WriteFile(dir + "/reject/marker_outside_image.bin", Serialize(p));
  p = base;
  p.mutable_marker_frame()->add_markers()->CopyFrom(base.marker_frame().markers(0));
  WriteFile(dir + "/reject/extra_marker.bin", Serialize(p));
  p = base;
  p.mutable_marker_frame()->set_node_id(0);
  WriteFile(dir + "/reject/node_zero.bin", Serialize(p));
  p.Clear();
  p.set_version(1);
  p.mutable_control()->set_node_id(1);
  WriteFile(dir + "/reject/control_without_command.bin", Serialize(p));
  p.mutable_control()->mutable_preview_request()->set_downscale(3);
  WriteFile(dir + "/reject/preview_bad_downscale.bin", Serialize(p));
  p.Clear();
  p.set_version(1);
  p.mutable_marker_frame();
  WriteFile(dir + "/reject/empty_frame_fields.bin", Serialize(p));
  p.Clear();
  p.set_version(1);
  p.mutable_control_ack()->set_node_id(5);
  p.mutable_control_ack()->set_result(mocap::v1::CONTROL_RESULT_REJECTED);
  WriteFile(dir + "/reject/ack_rejected_without_reason.bin", Serialize(p));

  // Envelopes, sealed by the firmware's code under the golden key, and ones that must not open.
  uint8_t key[32];
  golden_envelope_key(key);
  if (mn_envelope_init() != 0) return 1;
  std::string sealed_first;
  for (int i = 0; i < GOLDEN_ENVELOPE_COUNT; ++i) {
    const golden_envelope* g = golden_envelope_at(i);
    golden_vector_build(g->packet_vector, &packet);
    size_t n = 0;
    uint8_t out[MN_ENVELOPE_MAX_DATAGRAM];
    mn_wire_encode(&packet, buf, sizeof buf, &n, nullptr);
    mn_envelope env{g->direction, g->key_id, g->node_id, g->counter, buf, n};
    size_t sealed = 0;
    if (mn_envelope_seal(&env, key, out, sizeof out, &sealed, nullptr) != 0) return 1;
    const std::string bytes(reinterpret_cast<char*>(out), sealed);
    if (i == 0) sealed_first = bytes;
    WriteFile(dir + "/" + g->name + ".bin", bytes);
  }
  const std::string e = sealed_first;
  auto with = [&](size_t at, char value) {
    std::string b = e;
    b[at] = value;
    return b;
  };
  WriteFile(dir + "/reject_envelope/tag_flipped.bin", with(e.size() - 1, static_cast<char>(e.back() ^ 1)));
  WriteFile(dir + "/reject_envelope/payload_flipped.bin", with(20, static_cast<char>(e[20] ^ 0x40)));
  WriteFile(dir + "/reject_envelope/counter_changed.bin", with(8, static_cast<char>(e[8] + 1)));
  WriteFile(dir + "/reject_envelope/node_changed.bin", with(4, 8));
  WriteFile(dir + "/reject_envelope/key_id_changed.bin", with(2, 2));
  WriteFile(dir + "/reject_envelope/direction_changed.bin", with(1, 1));
  WriteFile(dir + "/reject_envelope/key_id_zero.bin", with(2, 0));
  WriteFile(dir + "/reject_envelope/not_an_envelope.bin", with(0, 0x08));
  WriteFile(dir + "/reject_envelope/truncated.bin", e.substr(0, e.size() - 5));
  WriteFile(dir + "/reject_envelope/header_only.bin", e.substr(0, 16));
  WriteFile(dir + "/reject_envelope/oversized.bin", e + std::string(1401 - e.size(), '\0'));
  std::cout << "golden vectors written to " << dir << "\n";
  return 0;
}
