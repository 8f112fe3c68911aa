// The .mca archive: CompressedTrajectories as a versioned little-endian binary file. Layout
// (version 1; every count is checked against the limits in trajectory_pca.h and the bytes left
// before anything is allocated):
//   magic    8 bytes "MOCAPMCA"
//   version  u32 = 1
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
//   blocks   window-major (all groups of window 0, then window 1, ...), per block:
//            u8 K (components, <= min(window frames, 3 x group size, 255)),
//            f32 mean[3 x size], then when K > 0:
//              f32 time_step (> 0); per component k: the window's frames of time[t][k] as
//                zigzag varints of t = 0's value, t = 1's first difference and then second
//                differences;
//              per component k: f32 weight_step (> 0), then 3 x size zigzag varints weights[c][k]
//            every integer within +-(2^29 - 1) once summed back
//   nothing after the last block.
// Varints are unsigned LEB128 of at most 5 bytes; zigzag maps 0, -1, 1, -2 ... to 0, 1, 2, 3 ... Window-major blocks let a reader decode the
// start of a long take without the rest.
// Errors: std::runtime_error "<source>: <reason>" (the io layer's rule), reason naming the field.
#pragma once

#include <string>

#include "archive/trajectory_pca.h"

namespace mocap {

constexpr uint32_t kArchiveVersion = 1;

std::string EncodeArchive(const CompressedTrajectories& compressed);
CompressedTrajectories DecodeArchive(const std::string& bytes, const std::string& source);

void WriteArchiveFile(const CompressedTrajectories& compressed, const std::string& path);
CompressedTrajectories ReadArchiveFile(const std::string& path);

// True when the path ends in .mca (any case).
bool IsArchivePath(const std::string& path);

}  // namespace mocap
