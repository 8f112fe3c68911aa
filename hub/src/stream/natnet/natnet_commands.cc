// NatNet requests answered (see natnet_commands.h).
#include "stream/natnet/natnet_commands.h"

#include <cctype>

namespace mocap::stream::natnet {
namespace {

constexpr int32_t kOk = 0;
constexpr int32_t kFailed = 1;

bool Same(const std::string& a, const char* b) {
  size_t i = 0;
  for (; i < a.size() && b[i]; ++i)
    if (std::tolower(static_cast<unsigned char>(a[i])) != std::tolower(static_cast<unsigned char>(b[i]))) return false;
  return i == a.size() && !b[i];
}

Reply Command(const std::string& line, const Model& model, CommandState* state) {
  const size_t comma = line.find(',');
  const std::string name = line.substr(0, comma);
  const bool has_args = comma != std::string::npos;
  const std::string args = has_args ? line.substr(comma + 1) : "";
  Reply r;
  if (Same(name, "Bitstream")) {
    if (!has_args) {
      r.packet = EncodeResponseString("Bitstream," + ToString(state->version));
      return r;
    }
    Version asked;
    if (ParseVersion(args, &asked) && Supported(asked)) {
      state->version = asked;
      state->info.version = asked;
      r.packet = EncodeResponseInt(kOk);
      return r;
    }
  } else if (Same(name, "UnitsToMillimeters") && !has_args) {
    r.packet = EncodeResponseFloat(1000.0f);
    return r;
  } else if (Same(name, "FrameRate") && !has_args) {
    r.packet = EncodeResponseFloat(static_cast<float>(model.rate_hz));
    return r;
  } else if ((Same(name, "CurrentMode") || Same(name, "LiveMode")) && !has_args) {
    r.packet = EncodeResponseInt(kOk);
    return r;
  }
  r.packet = EncodeResponseInt(kFailed);
  r.failed = true;
  return r;
}

}  // namespace

Reply Answer(const Request& request, const Model& model, CommandState* state) {
  Reply r;
  if (!request.ok) {
    r.packet = EncodeUnrecognized();
    r.failed = true;
    return r;
  }
  switch (request.id) {
    case kConnect:
      state->info.version = state->version;
      r.packet = EncodeServerInfo(state->info);
      r.subscription = Subscription::kSubscribe;
      return r;
    case kKeepAlive:
      r.subscription = Subscription::kKeepAlive;
      return r;
    case kDisconnect:
      r.subscription = Subscription::kUnsubscribe;
      return r;
    case kRequestModelDef:
      r.packet = EncodeModelDef(model, state->version);
      return r;
    case kRequestFrameOfData:
      r.send_frame = true;
      return r;
    case kRequest:
      return Command(request.command, model, state);
    default:
      r.packet = EncodeUnrecognized();
      r.failed = true;
      return r;
  }
}

}  // namespace mocap::stream::natnet
