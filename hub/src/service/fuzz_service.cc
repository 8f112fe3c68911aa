// libFuzzer target: arbitrary datagrams through the decoder into the service's consumers of node
// traffic (registry, preview assembler, control requests), as serve will feed them.
#include <cstddef>
#include <cstdint>

#include "service/control_requests.h"
#include "service/node_registry.h"
#include "service/preview_assembler.h"
#include "wire/packet.h"

namespace {

// Previews up to 1 MiB keep each run fast; the size limit itself is still exercised.
mocap::service::PreviewAssemblerOptions SmallPreviews() {
  mocap::service::PreviewAssemblerOptions options;
  options.max_image_bytes = 1u << 20;
  return options;
}

struct Service {
  mocap::service::NodeRegistry registry;
  mocap::service::PreviewAssembler previews{SmallPreviews()};
  mocap::service::ControlRequests requests;
  uint64_t now_ns = 0;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static Service service;
  service.now_ns += 10'000'000;
  if (service.requests.pending() < 8) {
    mocap::v1::Control stop;
    stop.mutable_stop();
    service.requests.Submit(1 + static_cast<uint32_t>(service.now_ns % 5), {stop, stop}, service.now_ns);
  }
  const mocap::wire::DecodeResult decoded = mocap::wire::Decode(data, size);
  if (!decoded.ok) {
    service.registry.OnMalformed("fuzz:1", decoded.reason, service.now_ns);
    return 0;
  }
  service.registry.OnPacket(decoded.packet, "fuzz:1", service.now_ns);
  if (decoded.packet.has_preview_chunk()) {
    mocap::service::PreviewImage image;
    if (service.previews.Add(decoded.packet.preview_chunk(), service.now_ns, &image) ==
        mocap::service::PreviewAssembler::Outcome::kComplete)
      mocap::service::EncodePng(image);
  }
  if (decoded.packet.has_control_ack()) service.requests.OnAck(decoded.packet.control_ack(), service.now_ns);
  service.registry.Tick(service.now_ns);
  service.requests.Tick(service.now_ns);
  service.previews.DiscardStale(service.now_ns);
  return 0;
}
