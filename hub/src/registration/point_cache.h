// Point caches Blender reads (its Mesh Cache modifier reads both; its MDD importer makes one
// shape key per frame): per-frame vertex positions of one mesh, in the mesh's vertex order.
//   .pc2 (little-endian): "POINTCACHE2\0", i32 version 1, i32 vertices, f32 start frame 0, f32
//        sampling 1 (one sample per frame), i32 frames; then frames x vertices x 3 f32.
//   .mdd (big-endian): i32 frames, i32 vertices, f32 time of each frame (s), then frames x
//        vertices x 3 f32.
// Sample i is scene frame i in the Mesh Cache modifier's default Frame time mode.
// Errors: std::invalid_argument for another extension or a wrong count; std::runtime_error
// "<file>: <reason>" for the file.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace mocap {

enum class PointCacheFormat { kPc2, kMdd };

// From the extension, .pc2 or .mdd (any case).
PointCacheFormat PointCacheFormatOf(const std::string& path);

class PointCacheWriter {
 public:
  PointCacheWriter() = default;
  ~PointCacheWriter();
  PointCacheWriter(const PointCacheWriter&) = delete;
  PointCacheWriter& operator=(const PointCacheWriter&) = delete;

  // Both formats state the frame count up front; rate_hz gives the MDD times.
  void Open(const std::string& path, size_t vertices, size_t frames, double rate_hz);
  void WriteFrame(const std::vector<Eigen::Vector3d>& vertices);
  // Refuses to close a file with fewer frames than announced.
  void Close();

 private:
  void PutFloat(float value);
  void PutInt(int32_t value);
  void Fail(const std::string& reason) const;

  std::FILE* file_ = nullptr;
  std::string path_;
  PointCacheFormat format_ = PointCacheFormat::kPc2;
  size_t vertices_ = 0, frames_ = 0, written_ = 0;
};

}  // namespace mocap
