// Writing an edited take: the marker file (TRC or C3D by extension, io/trajectory_file.h) and
// beside it the side file that says which samples were filled (NAME.filled.tsv for NAME.trc or
// NAME.c3d: one row per filled stretch, marker, first and last frame, method; every other present
// sample is measured). A C3D also says it in its residual words, the standard's convention:
// -1 a gap, 0 a computed (filled) point, a positive residual a measured one. Our processed results
// carry no residual per sample, so measured points get residual 1 with no camera bits: the float
// word 256 (the residual in the word's high byte, the camera mask in its low byte, as ezc3d reads
// and writes float files: ezc3d reads this residual as 1.0).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "edit/edited_take.h"

namespace mocap::edit {

constexpr float kMeasuredResidual = 256.0f;  // the residual word: residual 1, no camera bits

struct FilledStretch {
  std::string marker;
  uint64_t first_frame = 0, last_frame = 0;
  FillMethod method = FillMethod::kSpline;
};

// Runs of consecutive frames of one column filled by one method, by column then frame.
std::vector<FilledStretch> FilledStretches(const EditedTake& take);

// "out.trc" -> "out.filled.tsv".
std::string FilledSidePath(const std::string& output);

// Writes `path` and its side file. Errors: io's (std::runtime_error "<file>: <reason>",
// std::invalid_argument for an extension that is neither .trc nor .c3d).
void WriteEditedTake(const EditedTake& take, const std::string& path);

}  // namespace mocap::edit
