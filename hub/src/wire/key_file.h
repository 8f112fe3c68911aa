// Wire key files, hub side: the format firmware/node/keyfile.h reads, parsed, written and
// generated here (`mocap-hub keys`, the hub's keys directory):
//     node = 3
//     key = 2 <64 hex digits>      the first key signs what a side sends
//     key = 1 <64 hex digits>      every listed key is accepted (a change-over holds two)
// A key file is a secret: written with mode 0600 by an atomic rename, refused when group or
// others may read it. Error policy: ParseKeyFile throws std::invalid_argument naming origin:line;
// the file functions throw std::runtime_error naming the path.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "wire/datagram_envelope.h"

namespace mocap::wire {

constexpr size_t kMaxKeysPerFile = 2;
constexpr size_t kMaxKeyFileBytes = 4096;

struct WireKeyEntry {
  uint8_t id = 0;  // 1..255
  WireKey key{};
};

struct KeyFile {
  uint32_t node_id = 0;             // 1..4095
  std::vector<WireKeyEntry> keys;   // keys[0] signs; 1 or 2 entries with distinct ids
  const WireKeyEntry* Find(uint8_t id) const;
};

KeyFile ParseKeyFile(const std::string& text, const std::string& origin);
std::string FormatKeyFile(const KeyFile& file);
KeyFile ReadKeyFile(const std::string& path);
// Writes atomically (temporary file, fsync, rename) with mode 0600.
void WriteKeyFile(const std::string& path, const KeyFile& file);
// 32 bytes from libsodium's CSPRNG.
WireKey GenerateKey();
// The hub's keys directory names node N's file node-N.key.
std::string KeyFileName(uint32_t node_id);

}  // namespace mocap::wire
