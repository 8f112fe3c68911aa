// libFuzzer target: arbitrary datagrams on the stream port. Every input gets an answer: a
// request, or a reason; a request asks for known parts only.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "stream/stream_encoding.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const mocap::stream::StreamRequest r = mocap::stream::DecodeStreamRequest(data, size);
  if (r.ok != r.reason.empty()) std::abort();
  if (r.ok && r.subscribe && (r.parts == 0 || (r.parts & ~mocap::stream::kAllParts))) std::abort();
  return 0;
}
