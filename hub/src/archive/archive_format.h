// The .mca archive: CompressedTrajectories as a versioned little-endian binary file. Layout
// (version 2; every count is checked against the limits in trajectory_pca.h and the bytes left
// before anything is allocated; version 1, the plain-varint blocks, is refused by name):
//   magic    8 bytes "MOCAPMCA"
//   version  u32 = 2
//   rate_hz  f64 (> 0)
//   markers  u32 (1..4096)    frames u32 (>= 1; frames x markers <= 2^28)
//   window   u32 (1..4096)    frames per PCA window
//   numbering u8: 0 = contiguous, 1 = listed; then u64 first frame number; when listed,
//            frames - 1 varint increments (1..2^32 - 1)
//   names    per marker: u8 length (1..255), bytes
//   groups   u32 count (1..markers); per group u32 size, size x u32 marker index; every marker in
//            exactly one group
//   gaps     per marker: varint run count (1..frames + 1), runs as varints, alternately present
//            and missing, present first, summing to frames
//   windows  per window: varint chunk length L (at least 5, and at least a byte per 1024 of the
//            window's frames x markers), then L bytes of one range-coded stream (range_coder.h;
//            its adaptive models start afresh in every window) read exactly to its end, holding
//            the window's blocks:
//              first a bit: 1 when the means are relative (the encoder writes 0 in the first
//              window only, so a window that starts a file may start any file of its layout);
//              then per group: K (components, <= min(window frames, 3 x group size));
//              per channel the quantised mean (steps of kArchiveMeanStepMm): when relative its
//              change from the same marker's and axis's mean in the window before, else itself;
//              when K > 0: f32 time_step (> 0) as 32 plain bits; per component k the window's
//                frames of time[t][k]: t = 0's value, t = 1's first difference, then second
//                differences (modelled by component and by the size of the difference before);
//              per component k: f32 weight_step (> 0), then the 3 x size weights[c][k]
//            every integer within +-(2^29 - 1) once summed back
//   nothing after the last window.
// Varints are unsigned LEB128 of at most 5 bytes in their shortest form. Window-major chunks let a
// reader decode the start of a long take without the rest.
// Errors: std::runtime_error "<source>: <reason>" (the io layer's rule), reason naming the field.
#pragma once

#include <string>

#include "archive/trajectory_pca.h"

namespace mocap {

constexpr uint32_t kArchiveVersion = 2;

std::string EncodeArchive(const CompressedTrajectories& compressed);
CompressedTrajectories DecodeArchive(const std::string& bytes, const std::string& source);

void WriteArchiveFile(const CompressedTrajectories& compressed, const std::string& path);
CompressedTrajectories ReadArchiveFile(const std::string& path);

// True when the path ends in .mca (any case).
bool IsArchivePath(const std::string& path);

}  // namespace mocap
