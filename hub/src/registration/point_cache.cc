// PC2 and MDD point-cache writing (see point_cache.h).
#include "registration/point_cache.h"

#include <algorithm>
#include <cctype>
#include <climits>
#include <cstring>
#include <stdexcept>

namespace mocap {

PointCacheFormat PointCacheFormatOf(const std::string& path) {
  const size_t dot = path.find_last_of('.');
  std::string ext = dot == std::string::npos ? "" : path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == "pc2") return PointCacheFormat::kPc2;
  if (ext == "mdd") return PointCacheFormat::kMdd;
  throw std::invalid_argument("'" + path + "': point caches are .pc2 or .mdd");
}

PointCacheWriter::~PointCacheWriter() {
  if (file_ != nullptr) std::fclose(file_);
}

void PointCacheWriter::Fail(const std::string& reason) const { throw std::runtime_error(path_ + ": " + reason); }

void PointCacheWriter::PutInt(int32_t value) {
  uint32_t bits;
  std::memcpy(&bits, &value, 4);
  unsigned char raw[4];
  for (int i = 0; i < 4; ++i) {
    const int shift = format_ == PointCacheFormat::kMdd ? 8 * (3 - i) : 8 * i;
    raw[i] = static_cast<unsigned char>((bits >> shift) & 0xff);
  }
  if (std::fwrite(raw, 1, 4, file_) != 4) Fail("write failed");
}

void PointCacheWriter::PutFloat(float value) {
  int32_t bits;
  std::memcpy(&bits, &value, 4);
  PutInt(bits);
}

void PointCacheWriter::Open(const std::string& path, size_t vertices, size_t frames, double rate_hz) {
  format_ = PointCacheFormatOf(path);
  if (vertices == 0 || vertices > INT32_MAX / 3 || frames == 0 || frames > INT32_MAX)
    throw std::invalid_argument("point cache: " + std::to_string(vertices) + " vertices x " + std::to_string(frames) +
                                " frames is outside what the format holds");
  if (!(rate_hz > 0.0)) throw std::invalid_argument("point cache: rate " + std::to_string(rate_hz) + " Hz must be > 0");
  path_ = path;
  file_ = std::fopen(path.c_str(), "wb");
  if (file_ == nullptr) Fail("cannot open for writing");
  vertices_ = vertices;
  frames_ = frames;
  written_ = 0;
  if (format_ == PointCacheFormat::kPc2) {
    const char magic[12] = {'P', 'O', 'I', 'N', 'T', 'C', 'A', 'C', 'H', 'E', '2', '\0'};
    if (std::fwrite(magic, 1, sizeof(magic), file_) != sizeof(magic)) Fail("write failed");
    PutInt(1);
    PutInt(static_cast<int32_t>(vertices));
    PutFloat(0.0f);
    PutFloat(1.0f);
    PutInt(static_cast<int32_t>(frames));
  } else {
    PutInt(static_cast<int32_t>(frames));
    PutInt(static_cast<int32_t>(vertices));
    for (size_t i = 0; i < frames; ++i) PutFloat(static_cast<float>(static_cast<double>(i) / rate_hz));
  }
}

void PointCacheWriter::WriteFrame(const std::vector<Eigen::Vector3d>& vertices) {
  if (file_ == nullptr) throw std::logic_error("PointCacheWriter::WriteFrame before Open");
  if (vertices.size() != vertices_)
    throw std::invalid_argument("point cache: a frame of " + std::to_string(vertices.size()) + " vertices, the file holds " +
                                std::to_string(vertices_));
  if (written_ >= frames_) throw std::invalid_argument("point cache: more than the " + std::to_string(frames_) + " frames announced");
  for (const Eigen::Vector3d& v : vertices)
    for (int a = 0; a < 3; ++a) PutFloat(static_cast<float>(v[a]));
  ++written_;
}

void PointCacheWriter::Close() {
  if (file_ == nullptr) return;
  std::FILE* file = file_;
  file_ = nullptr;
  const bool failed = std::ferror(file) != 0;
  if (std::fclose(file) != 0 || failed) Fail("write failed");
  if (written_ != frames_)
    Fail(std::to_string(written_) + " frames written of the " + std::to_string(frames_) + " announced");
}

}  // namespace mocap
