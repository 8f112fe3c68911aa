// Session loading through the ingest layer's SessionReader.
#include "calib/session_frames.h"

#include <stdexcept>

#include "ingest/session.h"

namespace mocap {

std::vector<FrameSet> LoadSessionFrames(const std::string& dir, std::vector<std::string>* warnings) {
  SessionReader reader;
  reader.Open(dir);
  std::vector<FrameSet> frames;
  FrameSet set;
  while (reader.Next(&set)) frames.push_back(set);
  if (warnings != nullptr) {
    for (const std::string& warning : reader.warnings()) warnings->push_back(warning);
  }
  if (frames.empty()) throw std::runtime_error(dir + ": the session holds no frames");
  return frames;
}

}  // namespace mocap
