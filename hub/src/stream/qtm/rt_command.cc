// The RT command parser (see rt_command.h).
#include "stream/qtm/rt_command.h"

#include <arpa/inet.h>

#include <algorithm>
#include <cctype>
#include <vector>

namespace mocap::stream::qtm {
namespace {

// No valid command comes near this; longer lines are refused before they are split.
constexpr size_t kMaxCommandLine = 512;
constexpr size_t kMaxWords = 32;

std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

Command Fail(std::string why) {
  Command c;
  c.error = std::move(why);
  return c;
}

// A decimal number in [lo, hi] made of digits only.
bool ParseNumber(const std::string& s, uint32_t lo, uint32_t hi, uint32_t* value) {
  if (s.empty() || s.size() > 9) return false;
  uint32_t v = 0;
  for (char ch : s) {
    if (ch < '0' || ch > '9') return false;
    v = v * 10 + static_cast<uint32_t>(ch - '0');
  }
  if (v < lo || v > hi) return false;
  *value = v;
  return true;
}

bool ComponentBit(const std::string& word, uint32_t* bit) {
  static const struct { const char* name; uint32_t bit; } kNames[] = {
      {"3d", k3d},       {"3dres", k3dRes},     {"3dnolabels", k3dNoLabels}, {"3dnolabelsres", k3dNoLabelsRes},
      {"6d", k6d},       {"6dres", k6dRes},     {"6deuler", k6dEuler},       {"6deulerres", k6dEulerRes},
      {"all", kAllComponents}};
  for (const auto& n : kNames)
    if (word == n.name) return *bit = n.bit, true;
  return false;
}

// Components QTM knows but the hub has no data for: refused by name rather than as unknown.
bool KnownUnsupportedComponent(const std::string& word) {
  static const char* kNames[] = {"2d", "2dlin", "analog", "analogsingle", "force", "forcesingle", "image",
                                 "gazevector", "eyetracker", "timecode", "skeleton", "skeleton:global"};
  // Analog:1,2 and the like carry arguments after a colon; skeleton:global is a name.
  const std::string base = word.rfind("skeleton", 0) == 0 ? word : word.substr(0, word.find(':'));
  return std::any_of(std::begin(kNames), std::end(kNames), [&](const char* n) { return base == n; });
}

// Components from words[first...]; at least one.
bool ParseComponents(const std::vector<std::string>& words, size_t first, uint32_t* mask, std::string* error) {
  *mask = 0;
  for (size_t i = first; i < words.size(); ++i) {
    uint32_t bit = 0;
    if (ComponentBit(words[i], &bit)) {
      *mask |= bit;
    } else if (KnownUnsupportedComponent(words[i])) {
      *error = "Component not available: " + words[i];
      return false;
    } else {
      *error = "Parse error: unknown component '" + words[i] + "'";
      return false;
    }
  }
  if (*mask == 0) {
    *error = "Parse error: no component given";
    return false;
  }
  return true;
}

Command ParseVersion(const std::vector<std::string>& words) {
  Command c;
  c.kind = CommandKind::kVersion;
  if (words.size() == 1) return c.ok = true, c;
  if (words.size() != 2) return Fail("Parse error: Version takes one argument");
  const std::string& v = words[1];
  const size_t dot = v.find('.');
  uint32_t major = 0, minor = 0;
  if (dot == std::string::npos || !ParseNumber(v.substr(0, dot), 0, 99, &major) ||
      !ParseNumber(v.substr(dot + 1), 0, 999, &minor))
    return Fail("Parse error: version must be n.n");
  if (major != 1 || minor < 1 || minor > static_cast<uint32_t>(kMaxMinorVersion)) return Fail("Version NOT supported");
  c.version_minor = static_cast<int>(minor);
  c.ok = true;
  return c;
}

Command ParseGetParameters(const std::vector<std::string>& words) {
  Command c;
  c.kind = CommandKind::kGetParameters;
  if (words.size() < 2) return Fail("Parse error: GetParameters needs All or General, 3D, 6D");
  for (size_t i = 1; i < words.size(); ++i) {
    const std::string& w = words[i];
    if (w == "all") c.parameters |= kAllParameters;
    else if (w == "general") c.parameters |= kGeneral;
    else if (w == "3d") c.parameters |= k3dParameters;
    else if (w == "6d") c.parameters |= k6dParameters;
    else return Fail("Parameters not available: " + w);
  }
  c.ok = true;
  return c;
}

Command ParseStreamFrames(const std::vector<std::string>& words) {
  Command c;
  if (words.size() == 2 && words[1] == "stop") {
    c.kind = CommandKind::kStreamFramesStop;
    c.ok = true;
    return c;
  }
  c.kind = CommandKind::kStreamFrames;
  if (words.size() < 3) return Fail("Parse error: StreamFrames needs a rate and components");
  const std::string& rate = words[1];
  if (rate == "allframes") {
    c.rate = FrameRate::kAllFrames;
  } else if (rate.rfind("frequency:", 0) == 0) {
    c.rate = FrameRate::kFrequency;
    if (!ParseNumber(rate.substr(10), 1, 100000, &c.rate_value)) return Fail("Parse error: bad Frequency:n");
  } else if (rate.rfind("frequencydivisor:", 0) == 0) {
    c.rate = FrameRate::kFrequencyDivisor;
    if (!ParseNumber(rate.substr(17), 1, 100000, &c.rate_value)) return Fail("Parse error: bad FrequencyDivisor:n");
  } else {
    return Fail("Parse error: StreamFrames rate must be AllFrames, Frequency:n or FrequencyDivisor:n");
  }
  size_t first = 2;
  if (words[2] == "udp" || words[2].rfind("udp:", 0) == 0) {
    const std::string& udp = words[2];
    const size_t last = udp.rfind(':');
    uint32_t port = 0;
    if (last == std::string::npos || last < 3 || !ParseNumber(udp.substr(last + 1), 1023, 65535, &port))
      return Fail("Parse error: UDP needs a port 1023-65535 (UDP[:address]:port)");
    if (last > 3) {
      c.udp_address = udp.substr(4, last - 4);
      in_addr addr{};
      if (inet_pton(AF_INET, c.udp_address.c_str(), &addr) != 1)
        return Fail("Parse error: UDP address must be a dotted IPv4 address");
    }
    c.udp = true;
    c.udp_port = static_cast<uint16_t>(port);
    first = 3;
  }
  if (!ParseComponents(words, first, &c.components, &c.error)) return c;
  c.ok = true;
  return c;
}

}  // namespace

uint32_t ComponentType(Component c) {
  switch (c) {
    case k3d: return 1;
    case k3dNoLabels: return 2;
    case k6d: return 5;
    case k6dEuler: return 6;
    case k3dRes: return 9;
    case k3dNoLabelsRes: return 10;
    case k6dRes: return 11;
    case k6dEulerRes: return 12;
  }
  return 0;
}

Command ParseCommand(const std::string& text) {
  std::string line = text;
  while (!line.empty() && (line.back() == '\0' || line.back() == '\n' || line.back() == '\r')) line.pop_back();
  if (line.size() > kMaxCommandLine) return Fail("Parse error: command too long");
  for (unsigned char ch : line)
    if (ch < 0x20 && ch != '\t') return Fail("Parse error: control character in command");
    else if (ch >= 0x7f) return Fail("Parse error: command must be ASCII");
  std::vector<std::string> words;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    const size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > start) {
      if (words.size() == kMaxWords) return Fail("Parse error: too many words");
      words.push_back(Lower(line.substr(start, i - start)));
    }
  }
  if (words.empty()) return Fail("Parse error: empty command");
  const std::string& name = words[0];
  auto bare = [&](CommandKind kind) {
    if (words.size() != 1) return Fail("Parse error: " + name + " takes no argument");
    Command c;
    c.kind = kind;
    c.ok = true;
    return c;
  };
  if (name == "version") return ParseVersion(words);
  if (name == "qtmversion") return bare(CommandKind::kQtmVersion);
  if (name == "byteorder") return bare(CommandKind::kByteOrder);
  if (name == "getstate") return bare(CommandKind::kGetState);
  if (name == "quit" || name == "disconnect") return bare(CommandKind::kQuit);
  if (name == "getparameters") return ParseGetParameters(words);
  if (name == "streamframes") return ParseStreamFrames(words);
  if (name == "getcurrentframe") {
    Command c;
    c.kind = CommandKind::kGetCurrentFrame;
    if (words.size() < 2) return Fail("Parse error: GetCurrentFrame needs components");
    if (!ParseComponents(words, 1, &c.components, &c.error)) return c;
    c.ok = true;
    return c;
  }
  static const char* kRefused[] = {"takecontrol", "releasecontrol", "new", "close", "start", "stop", "load",
                                   "save", "loadproject", "getcapturec3d", "getcaptureqtm", "trig",
                                   "setqtmevent", "event", "reprocess", "led", "calibrate", "checklicense"};
  for (const char* refused : kRefused)
    if (name == refused) return Fail("Command not supported by mocap-hub: " + name);
  return Fail("Parse error: unknown command '" + name.substr(0, 64) + "'");
}

}  // namespace mocap::stream::qtm
