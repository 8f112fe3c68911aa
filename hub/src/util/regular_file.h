// Whole-file reads of outside files with a bound. A path can name anything: /dev/zero never ends,
// a FIFO blocks until a writer comes and then ends when it likes, a directory or a huge file is
// no input either. Every reader that takes a file whole (JSON documents, hub.conf, C3D, body
// poses, .mcd) reads through ReadRegularFile, so such a path costs no memory and no wait, only a
// clear error. (Line-based readers bound each line instead: util/bounded_line.h.)
#pragma once

#include <cstddef>
#include <string>

namespace mocap {

// The bytes of the regular file at `path`, if it holds at most max_bytes. Opens without blocking
// (a FIFO is refused, not waited on) and looks at the opened file's type, so nothing but a
// regular file is read. `kind` names what the file should be ("a JSON file") in the errors:
// std::runtime_error "<path>: cannot open: <errno text>", "<path>: not a regular file (a FIFO);
// <kind> is a regular file of at most <bound>", "<path>: larger than <bound>, the bound for
// <kind>", "<path>: read failed: <errno text>".
std::string ReadRegularFile(const std::string& path, size_t max_bytes, const std::string& kind);

// "64 KiB", "16 MiB", "4 GiB", or "N bytes" for a bound that is none of those.
std::string ByteSizeText(size_t bytes);

// Bound for recordings read whole (C3D trajectories, body pose tables, .mcd wand recordings):
// they grow with the capture. A one-hour 123-marker take at 240 Hz is 1.7 GB as float C3D and
// about as much as a pose table of a dozen bodies at that rate; a reader of such a file holds it and what it
// parses (more than the file), so beyond this bound memory, not the bound, would stop it.
constexpr size_t kMaxRecordingFileBytes = size_t{4} << 30;

}  // namespace mocap
