// The command language of the Qualisys RT protocol: one line of space-separated, case-insensitive
// words per command packet. ParseCommand turns a packet body into a typed command or a reason
// the client gets back in an error packet. Only the commands and components the hub can honour
// are accepted; QTM's control commands (TakeControl, Start, Save, ...) are recognised and refused
// by name. Pure code: no I/O, never throws.
#pragma once

#include <cstdint>
#include <string>

namespace mocap::stream::qtm {

// Data components of a data packet, as bits of a mask; the component type numbers are the
// protocol's.
enum Component : uint32_t {
  k3d = 1u << 0,
  k3dNoLabels = 1u << 1,
  k6d = 1u << 2,
  k6dEuler = 1u << 3,
  k3dRes = 1u << 4,
  k3dNoLabelsRes = 1u << 5,
  k6dRes = 1u << 6,
  k6dEulerRes = 1u << 7,
};
constexpr uint32_t kAllComponents = 0xff;
// The protocol's type number of one component bit.
uint32_t ComponentType(Component c);

// Parameter blocks GetParameters can answer.
enum ParameterBlock : uint32_t { kGeneral = 1u << 0, k3dParameters = 1u << 1, k6dParameters = 1u << 2 };
constexpr uint32_t kAllParameters = 0x7;

enum class CommandKind {
  kVersion,          // version empty: the client asks which one is in use
  kQtmVersion,
  kByteOrder,
  kGetState,
  kGetParameters,
  kGetCurrentFrame,
  kStreamFrames,
  kStreamFramesStop,
  kQuit,             // Quit / Disconnect: answered, then the connection is closed
};

enum class FrameRate { kAllFrames, kFrequency, kFrequencyDivisor };

// Protocol versions accepted: any 1.x (qtm-rt 3.x asks for 1.25 by default; newer clients ask
// for newer minors). The version only names the XML root: every component served keeps the
// layout protocol 1.25 documents whatever the client asked for.
constexpr int kMaxMinorVersion = 99;

struct Command {
  bool ok = false;
  std::string error;         // why not, when !ok (sent back as is)
  CommandKind kind = CommandKind::kVersion;
  int version_minor = 0;     // kVersion with an argument: 1.<minor>
  uint32_t parameters = 0;   // kGetParameters: ParameterBlock bits
  uint32_t components = 0;   // kGetCurrentFrame / kStreamFrames: Component bits
  FrameRate rate = FrameRate::kAllFrames;
  uint32_t rate_value = 0;   // Frequency:n (Hz) or FrequencyDivisor:n
  bool udp = false;          // StreamFrames ... UDP[:address]:port
  std::string udp_address;   // dotted IPv4; empty: the client's own address
  uint16_t udp_port = 0;
};

// `text` is the packet body (a trailing NUL is allowed). Lines longer than the protocol's
// commands ever are, control bytes and unknown words give !ok with a reason.
Command ParseCommand(const std::string& text);

}  // namespace mocap::stream::qtm
