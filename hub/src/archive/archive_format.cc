// The .mca archive's encoder and bounded decoder (layout in archive_format.h).
#include "archive/archive_format.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include "util/regular_file.h"

namespace mocap {
namespace {

constexpr char kMagic[8] = {'M', 'O', 'C', 'A', 'P', 'M', 'C', 'A'};

class ByteWriter {
 public:
  template <typename T>
  void Put(T value) {
    char raw[sizeof(T)];
    std::memcpy(raw, &value, sizeof(T));  // the hub's targets are little-endian (x86-64, aarch64)
    bytes_.append(raw, sizeof(T));
  }
  void PutVarint(uint32_t value) {
    while (value >= 0x80) {
      bytes_.push_back(static_cast<char>((value & 0x7f) | 0x80));
      value >>= 7;
    }
    bytes_.push_back(static_cast<char>(value));
  }
  void PutSigned(int64_t value) {
    PutVarint(static_cast<uint32_t>(value < 0 ? ((-(value + 1)) << 1) | 1 : value << 1));
  }
  void PutBytes(const std::string& text) { bytes_ += text; }
  std::string& bytes() { return bytes_; }

 private:
  std::string bytes_;
};

class ByteReader {
 public:
  ByteReader(const std::string& bytes, const std::string& source) : bytes_(bytes), source_(source) {}

  [[noreturn]] void Fail(const std::string& reason) const {
    throw std::runtime_error(source_ + ": " + reason + " (at byte " + std::to_string(offset_) + ")");
  }
  size_t Left() const { return bytes_.size() - offset_; }
  // Refuses `count` items of `size` bytes unless the file still holds them.
  void Need(uint64_t count, size_t size, const char* field) const {
    if (count > Left() / size)
      Fail(std::string(field) + ": " + std::to_string(count) + " items need more bytes than the " +
           std::to_string(Left()) + " left");
  }
  template <typename T>
  T Get(const char* field) {
    Need(1, sizeof(T), field);
    T value;
    std::memcpy(&value, bytes_.data() + offset_, sizeof(T));
    offset_ += sizeof(T);
    return value;
  }
  uint32_t GetVarint(const char* field) {
    uint32_t value = 0;
    for (int i = 0; i < 5; ++i) {
      const uint8_t byte = Get<uint8_t>(field);
      if (i == 4 && byte > 0x0f) Fail(std::string(field) + ": varint larger than 32 bits");
      value |= static_cast<uint32_t>(byte & 0x7f) << (7 * i);
      if (!(byte & 0x80)) {
        // One encoding per number, so that a decoded archive encodes back to its bytes.
        if (i > 0 && byte == 0) Fail(std::string(field) + ": varint not in its shortest form");
        return value;
      }
    }
    Fail(std::string(field) + ": varint longer than 5 bytes");
  }
  int64_t GetSigned(const char* field) {
    const uint32_t raw = GetVarint(field);
    return (raw & 1) ? -static_cast<int64_t>(raw >> 1) - 1 : static_cast<int64_t>(raw >> 1);
  }
  std::string GetBytes(size_t count, const char* field) {
    Need(count, 1, field);
    std::string out = bytes_.substr(offset_, count);
    offset_ += count;
    return out;
  }
  template <typename T>
  void GetArray(std::vector<T>* out, size_t count, const char* field) {
    Need(count, sizeof(T), field);
    out->resize(count);
    if (count > 0) std::memcpy(out->data(), bytes_.data() + offset_, count * sizeof(T));
    offset_ += count * sizeof(T);
  }

 private:
  const std::string& bytes_;
  const std::string& source_;
  size_t offset_ = 0;
};

// The time factors along t: the first value, the first difference, then second differences.
void PutTimeColumn(ByteWriter& out, const std::vector<int32_t>& time, size_t frames, size_t k, size_t k_count) {
  for (size_t t = 0; t < frames; ++t) {
    const int64_t now = time[t * k_count + k];
    const int64_t before = t >= 1 ? time[(t - 1) * k_count + k] : 0;
    const int64_t earlier = t >= 2 ? time[(t - 2) * k_count + k] : 0;
    out.PutSigned(t == 0 ? now : t == 1 ? now - before : now - 2 * before + earlier);
  }
}

void GetTimeColumn(ByteReader& in, std::vector<int32_t>* time, size_t frames, size_t k, size_t k_count) {
  int64_t before = 0, earlier = 0;
  for (size_t t = 0; t < frames; ++t) {
    const int64_t delta = in.GetSigned("time");
    const int64_t now = t == 0 ? delta : t == 1 ? before + delta : 2 * before - earlier + delta;
    if (now > kMaxArchiveInteger || now < -kMaxArchiveInteger)
      in.Fail("time: value " + std::to_string(now) + " is outside +-(2^29 - 1)");
    (*time)[t * k_count + k] = static_cast<int32_t>(now);
    earlier = before;
    before = now;
  }
}

bool Contiguous(const std::vector<uint64_t>& frame_numbers) {
  for (size_t i = 1; i < frame_numbers.size(); ++i)
    if (frame_numbers[i] != frame_numbers[i - 1] + 1) return false;
  return true;
}

void CheckFinite(ByteReader& reader, const std::vector<float>& values, const char* field) {
  for (float value : values)
    if (!std::isfinite(value)) reader.Fail(std::string(field) + ": not a finite number");
}

}  // namespace

std::string EncodeArchive(const CompressedTrajectories& compressed) {
  ByteWriter out;
  out.PutBytes(std::string(kMagic, sizeof(kMagic)));
  out.Put<uint32_t>(kArchiveVersion);
  out.Put<double>(compressed.rate_hz);
  out.Put<uint32_t>(static_cast<uint32_t>(compressed.names.size()));
  out.Put<uint32_t>(static_cast<uint32_t>(compressed.NumFrames()));
  out.Put<uint32_t>(static_cast<uint32_t>(compressed.window_frames));
  const bool contiguous = Contiguous(compressed.frame_numbers);
  out.Put<uint8_t>(contiguous ? 0 : 1);
  out.Put<uint64_t>(compressed.frame_numbers.front());
  if (!contiguous) {
    for (size_t i = 1; i < compressed.frame_numbers.size(); ++i) {
      const uint64_t step = compressed.frame_numbers[i] - compressed.frame_numbers[i - 1];
      if (step == 0 || step > UINT32_MAX)
        throw std::invalid_argument("archive: frame number step " + std::to_string(step) + " is outside 1..2^32-1");
      out.PutVarint(static_cast<uint32_t>(step));
    }
  }
  for (const std::string& name : compressed.names) {
    if (name.empty() || name.size() > 255)
      throw std::invalid_argument("archive: marker name '" + name + "' must be 1..255 bytes");
    out.Put<uint8_t>(static_cast<uint8_t>(name.size()));
    out.PutBytes(name);
  }
  out.Put<uint32_t>(static_cast<uint32_t>(compressed.groups.size()));
  for (const std::vector<int>& group : compressed.groups) {
    out.Put<uint32_t>(static_cast<uint32_t>(group.size()));
    for (int marker : group) out.Put<uint32_t>(static_cast<uint32_t>(marker));
  }
  for (const std::vector<uint32_t>& runs : compressed.gap_runs) {
    out.PutVarint(static_cast<uint32_t>(runs.size()));
    for (uint32_t run : runs) out.PutVarint(run);
  }
  for (const PcaBlock& block : compressed.blocks) {
    out.Put<uint8_t>(static_cast<uint8_t>(block.components));
    for (float v : block.mean) out.Put<float>(v);
    if (block.components == 0) continue;
    const size_t k_count = static_cast<size_t>(block.components);
    out.Put<float>(block.time_step);
    for (size_t k = 0; k < k_count; ++k) PutTimeColumn(out, block.time, block.time.size() / k_count, k, k_count);
    const size_t channels = block.mean.size();
    for (size_t k = 0; k < k_count; ++k) {
      out.Put<float>(block.weight_steps[k]);
      for (size_t c = 0; c < channels; ++c) out.PutSigned(block.weights[c * k_count + k]);
    }
  }
  return std::move(out.bytes());
}

CompressedTrajectories DecodeArchive(const std::string& bytes, const std::string& source) {
  ByteReader in(bytes, source);
  if (in.GetBytes(sizeof(kMagic), "magic") != std::string(kMagic, sizeof(kMagic)))
    in.Fail("magic: not a mocap archive (.mca starts with MOCAPMCA)");
  const uint32_t version = in.Get<uint32_t>("version");
  if (version != kArchiveVersion)
    in.Fail("version: " + std::to_string(version) + " is not supported (this reader knows version " +
            std::to_string(kArchiveVersion) + ")");
  CompressedTrajectories out;
  out.rate_hz = in.Get<double>("rate_hz");
  if (!(out.rate_hz > 0.0 && std::isfinite(out.rate_hz))) in.Fail("rate_hz: " + std::to_string(out.rate_hz) + " is not > 0");
  const uint32_t markers = in.Get<uint32_t>("markers");
  const uint32_t frames = in.Get<uint32_t>("frames");
  const uint32_t window = in.Get<uint32_t>("window");
  if (markers < 1 || markers > kMaxArchiveMarkers)
    in.Fail("markers: " + std::to_string(markers) + " is outside 1.." + std::to_string(kMaxArchiveMarkers));
  if (frames < 1 || static_cast<uint64_t>(frames) * markers > kMaxArchivePoints)
    in.Fail("frames: " + std::to_string(frames) + " x " + std::to_string(markers) + " markers is outside 1.." +
            std::to_string(kMaxArchivePoints) + " points");
  if (window < 1 || window > kMaxArchiveWindowFrames)
    in.Fail("window: " + std::to_string(window) + " is outside 1.." + std::to_string(kMaxArchiveWindowFrames));
  out.window_frames = static_cast<int>(window);
  // Every window holds every marker's mean (12 bytes) and each group's K: a short file cannot
  // claim a long take and make the decoder allocate it (at most window / 12 points per byte).
  in.Need((static_cast<uint64_t>(frames) + window - 1) / window, 12 * size_t{markers} + 1, "blocks");
  const uint8_t numbering = in.Get<uint8_t>("numbering");
  if (numbering > 1) in.Fail("numbering: " + std::to_string(numbering) + " is neither 0 (contiguous) nor 1 (listed)");
  out.frame_numbers.reserve(frames);
  out.frame_numbers.push_back(in.Get<uint64_t>("first frame"));
  for (uint32_t i = 1; i < frames; ++i) {
    uint64_t step = 1;
    if (numbering == 1) {
      step = in.GetVarint("frame increment");
      if (step == 0) in.Fail("frame increment: 0; frame numbers must increase");
    }
    if (out.frame_numbers.back() > UINT64_MAX - step) in.Fail("frame numbers: past 2^64");
    out.frame_numbers.push_back(out.frame_numbers.back() + step);
  }
  if (numbering == 1 && frames > 1 && out.frame_numbers.back() - out.frame_numbers.front() == frames - 1)
    in.Fail("numbering: 1 (listed) for contiguous frame numbers, which are written as 0");
  in.Need(markers, 2, "names");
  for (uint32_t i = 0; i < markers; ++i) {
    const uint8_t length = in.Get<uint8_t>("name length");
    if (length == 0) in.Fail("name length: 0 for marker " + std::to_string(i));
    out.names.push_back(in.GetBytes(length, "name"));
  }
  const uint32_t group_count = in.Get<uint32_t>("groups");
  if (group_count < 1 || group_count > markers)
    in.Fail("groups: " + std::to_string(group_count) + " is outside 1.." + std::to_string(markers));
  std::vector<bool> grouped(markers, false);
  for (uint32_t g = 0; g < group_count; ++g) {
    const uint32_t size = in.Get<uint32_t>("group size");
    if (size < 1 || size > markers) in.Fail("group size: " + std::to_string(size) + " is outside 1.." + std::to_string(markers));
    std::vector<uint32_t> indices;
    in.GetArray(&indices, size, "group markers");
    out.groups.emplace_back();
    for (uint32_t marker : indices) {
      if (marker >= markers || grouped[marker])
        in.Fail("group markers: marker " + std::to_string(marker) + " is out of range or in two groups");
      grouped[marker] = true;
      out.groups.back().push_back(static_cast<int>(marker));
    }
  }
  if (std::find(grouped.begin(), grouped.end(), false) != grouped.end()) in.Fail("groups: a marker is in no group");
  out.gap_runs.resize(markers);
  for (uint32_t marker = 0; marker < markers; ++marker) {
    const uint32_t count = in.GetVarint("gap run count");
    if (count < 1 || count > static_cast<uint64_t>(frames) + 1)
      in.Fail("gap run count: " + std::to_string(count) + " is outside 1.." + std::to_string(uint64_t{frames} + 1));
    in.Need(count, 1, "gap runs");
    uint64_t total = 0;
    for (uint32_t r = 0; r < count; ++r) {
      out.gap_runs[marker].push_back(in.GetVarint("gap run"));
      total += out.gap_runs[marker].back();
    }
    if (total != frames)
      in.Fail("gap runs: marker " + std::to_string(marker) + "'s runs cover " + std::to_string(total) + " frames, not " +
              std::to_string(frames));
  }
  const size_t windows = out.NumWindows();
  out.blocks.reserve(windows * group_count);
  for (size_t w = 0; w < windows; ++w) {
    const size_t window_frames = std::min<size_t>(window, frames - w * window);
    for (const std::vector<int>& group : out.groups) {
      PcaBlock block;
      const size_t channels = 3 * group.size();
      block.components = in.Get<uint8_t>("components");
      if (static_cast<size_t>(block.components) > std::min(window_frames, channels))
        in.Fail("components: " + std::to_string(block.components) + " is more than the window's rank " +
                std::to_string(std::min(window_frames, channels)));
      const size_t k = static_cast<size_t>(block.components);
      in.GetArray(&block.mean, channels, "mean");
      CheckFinite(in, block.mean, "mean");
      if (k > 0) {
        block.time_step = in.Get<float>("time step");
        if (!(block.time_step > 0.0f && std::isfinite(block.time_step))) in.Fail("time step: not a finite number > 0");
        in.Need(window_frames * k, 1, "time");  // a varint is at least a byte
        block.time.resize(window_frames * k);
        for (size_t q = 0; q < k; ++q) GetTimeColumn(in, &block.time, window_frames, q, k);
        in.Need(k, 4 + channels, "weights");
        block.weights.resize(channels * k);
        for (size_t q = 0; q < k; ++q) {
          block.weight_steps.push_back(in.Get<float>("weight step"));
          if (!(block.weight_steps.back() > 0.0f && std::isfinite(block.weight_steps.back())))
            in.Fail("weight step: not a finite number > 0");
          for (size_t c = 0; c < channels; ++c) {
            const int64_t w = in.GetSigned("weights");
            if (w > kMaxArchiveInteger || w < -kMaxArchiveInteger)
              in.Fail("weights: value " + std::to_string(w) + " is outside +-(2^29 - 1)");
            block.weights[c * k + q] = static_cast<int32_t>(w);
          }
        }
      }
      out.blocks.push_back(std::move(block));
    }
  }
  if (in.Left() != 0) in.Fail(std::to_string(in.Left()) + " bytes after the last block");
  return out;
}

void WriteArchiveFile(const CompressedTrajectories& compressed, const std::string& path) {
  const std::string bytes = EncodeArchive(compressed);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw std::runtime_error(path + ": cannot open for writing");
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) throw std::runtime_error(path + ": write failed");
}

CompressedTrajectories ReadArchiveFile(const std::string& path) {
  return DecodeArchive(ReadRegularFile(path, kMaxRecordingFileBytes, "a mocap archive (.mca)"), path);
}

bool IsArchivePath(const std::string& path) {
  if (path.size() < 4) return false;
  std::string ext = path.substr(path.size() - 4);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".mca";
}

}  // namespace mocap
