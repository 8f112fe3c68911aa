// The .mca archive's encoder and bounded decoder (layout in archive_format.h).
#include "archive/archive_format.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include "archive/range_coder.h"
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

// Adaptive models of one window's chunk (reset per window, so that each window decodes alone once
// the means before it are known): time factors by component (the first 8 apart, later ones
// together) and by the size of the previous second difference, weights by component.
struct WindowModels {
  uint16_t relative = 1 << 10;
  IntModel components, mean, time_start;
  IntModel time[8][3];
  IntModel weights[8];
};

size_t ComponentContext(size_t k) { return std::min<size_t>(k, 7); }
size_t SizeContext(int64_t value) { return value == 0 ? 0 : (value >= -2 && value <= 2) ? 1 : 2; }

// The time factors along t: the first value, the first difference, then second differences.
void PutTimeColumn(RangeEncoder& out, WindowModels& models, const std::vector<int32_t>& time, size_t frames, size_t k,
                   size_t k_count) {
  int64_t previous = 0;
  for (size_t t = 0; t < frames; ++t) {
    const int64_t now = time[t * k_count + k];
    const int64_t before = t >= 1 ? time[(t - 1) * k_count + k] : 0;
    const int64_t earlier = t >= 2 ? time[(t - 2) * k_count + k] : 0;
    const int64_t delta = t == 0 ? now : t == 1 ? now - before : now - 2 * before + earlier;
    if (delta > kMaxRangeCodedInteger || delta < -kMaxRangeCodedInteger)
      throw std::invalid_argument("archive: a time factor's second difference " + std::to_string(delta) +
                                  " is outside +-(2^29 - 1)");
    out.Int(t < 2 ? models.time_start : models.time[ComponentContext(k)][SizeContext(previous)],
            static_cast<int32_t>(delta));
    previous = delta;
  }
}

void GetTimeColumn(RangeDecoder& in, WindowModels& models, std::vector<int32_t>* time, size_t frames, size_t k,
                   size_t k_count) {
  int64_t before = 0, earlier = 0, previous = 0;
  for (size_t t = 0; t < frames; ++t) {
    const int64_t delta =
        in.Int(t < 2 ? models.time_start : models.time[ComponentContext(k)][SizeContext(previous)], "time");
    const int64_t now = t == 0 ? delta : t == 1 ? before + delta : 2 * before - earlier + delta;
    if (now > kMaxArchiveInteger || now < -kMaxArchiveInteger)
      throw std::runtime_error("time: value " + std::to_string(now) + " is outside +-(2^29 - 1)");
    (*time)[t * k_count + k] = static_cast<int32_t>(now);
    earlier = before;
    before = now;
    previous = delta;
  }
}

// The smallest chunk a window of `points` (frames x markers) may have: the coder's 5 bytes, and
// at least a byte per kMaxPointsPerByte points so that a short file cannot claim a long take.
constexpr uint64_t kMaxPointsPerByte = 1024;
uint64_t MinimumChunk(uint64_t points) { return std::max<uint64_t>(5, (points + kMaxPointsPerByte - 1) / kMaxPointsPerByte); }

// One window's blocks as a range-coded chunk; `means` holds every marker's quantised mean of the
// window before (0 before the first), each block's means coded as the change from it.
std::string EncodeWindow(const CompressedTrajectories& compressed, size_t w, std::vector<int32_t>& means) {
  RangeEncoder out;
  WindowModels models;
  // The first window's means are absolute (from 0), every later one's relative.
  if (w == 0) std::fill(means.begin(), means.end(), 0);
  out.Bit(models.relative, w > 0);
  for (size_t g = 0; g < compressed.groups.size(); ++g) {
    const PcaBlock& block = compressed.blocks[w * compressed.groups.size() + g];
    const std::vector<int>& group = compressed.groups[g];
    out.Int(models.components, block.components);
    for (size_t c = 0; c < block.mean.size(); ++c) {
      int32_t& before = means[3 * static_cast<size_t>(group[c / 3]) + c % 3];
      const int64_t change = int64_t{block.mean[c]} - before;
      if (change > kMaxRangeCodedInteger || change < -kMaxRangeCodedInteger)
        throw std::invalid_argument("archive: a mean moved " + std::to_string(change) + " steps between windows, past +-(2^29 - 1)");
      out.Int(models.mean, static_cast<int32_t>(change));
      before = block.mean[c];
    }
    if (block.components == 0) continue;
    const size_t k_count = static_cast<size_t>(block.components);
    out.Float(block.time_step);
    for (size_t k = 0; k < k_count; ++k) PutTimeColumn(out, models, block.time, block.time.size() / k_count, k, k_count);
    const size_t channels = block.mean.size();
    for (size_t k = 0; k < k_count; ++k) {
      out.Float(block.weight_steps[k]);
      for (size_t c = 0; c < channels; ++c) out.Int(models.weights[ComponentContext(k)], block.weights[c * k_count + k]);
    }
  }
  return out.Finish();
}

void DecodeBlock(RangeDecoder& in, WindowModels& models, const std::vector<int>& group, size_t window_frames,
                 std::vector<int32_t>& means, PcaBlock& block) {
  const size_t channels = 3 * group.size();
  block.components = in.Int(models.components, "components");
  if (block.components < 0 || static_cast<size_t>(block.components) > std::min(window_frames, channels))
    throw std::runtime_error("components: " + std::to_string(block.components) + " is outside 0..the window's rank " +
                             std::to_string(std::min(window_frames, channels)));
  block.mean.resize(channels);
  for (size_t c = 0; c < channels; ++c) {
    int32_t& before = means[3 * static_cast<size_t>(group[c / 3]) + c % 3];
    const int64_t now = int64_t{before} + in.Int(models.mean, "mean");
    if (now > kMaxArchiveInteger || now < -kMaxArchiveInteger)
      throw std::runtime_error("mean: value " + std::to_string(now) + " is outside +-(2^29 - 1)");
    block.mean[c] = before = static_cast<int32_t>(now);
  }
  const size_t k = static_cast<size_t>(block.components);
  if (k == 0) return;
  block.time_step = in.Float();
  if (!(block.time_step > 0.0f && std::isfinite(block.time_step))) throw std::runtime_error("time step: not a finite number > 0");
  block.time.resize(window_frames * k);
  for (size_t q = 0; q < k; ++q) GetTimeColumn(in, models, &block.time, window_frames, q, k);
  block.weights.resize(channels * k);
  for (size_t q = 0; q < k; ++q) {
    block.weight_steps.push_back(in.Float());
    if (!(block.weight_steps.back() > 0.0f && std::isfinite(block.weight_steps.back())))
      throw std::runtime_error("weight step: not a finite number > 0");
    for (size_t c = 0; c < channels; ++c) block.weights[c * k + q] = in.Int(models.weights[ComponentContext(q)], "weights");
  }
}

bool Contiguous(const std::vector<uint64_t>& frame_numbers) {
  for (size_t i = 1; i < frame_numbers.size(); ++i)
    if (frame_numbers[i] != frame_numbers[i - 1] + 1) return false;
  return true;
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
  std::vector<int32_t> means(3 * compressed.names.size(), 0);
  for (size_t w = 0; w < compressed.NumWindows(); ++w) {
    const std::string chunk = EncodeWindow(compressed, w, means);
    const size_t frames = std::min<size_t>(compressed.window_frames, compressed.NumFrames() - w * compressed.window_frames);
    if (chunk.size() < MinimumChunk(uint64_t{frames} * compressed.names.size()))
      throw std::invalid_argument("archive: window " + std::to_string(w) + " compresses to " + std::to_string(chunk.size()) +
                                  " bytes, under the format's byte per " + std::to_string(kMaxPointsPerByte) +
                                  " points; use shorter windows (--window-frames)");
    out.PutVarint(static_cast<uint32_t>(chunk.size()));
    out.PutBytes(chunk);
  }
  return std::move(out.bytes());
}

CompressedTrajectories DecodeArchive(const std::string& bytes, const std::string& source) {
  ByteReader in(bytes, source);
  if (in.GetBytes(sizeof(kMagic), "magic") != std::string(kMagic, sizeof(kMagic)))
    in.Fail("magic: not a mocap archive (.mca starts with MOCAPMCA)");
  const uint32_t version = in.Get<uint32_t>("version");
  if (version == 1)
    in.Fail("version: 1 (plain-varint blocks, before the range coder) is not supported; this reader knows version " +
            std::to_string(kArchiveVersion) + ": write the archive again with mocap-hub archive");
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
  // Every window's chunk holds at least a length byte and MinimumChunk of its points: a short
  // file cannot claim a long take and make the decoder allocate it.
  const uint64_t window_count = (static_cast<uint64_t>(frames) + window - 1) / window;
  in.Need(std::max(6 * window_count, (uint64_t{frames} * markers + kMaxPointsPerByte - 1) / kMaxPointsPerByte), 1, "blocks");
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
  out.blocks.resize(windows * group_count);
  std::vector<int32_t> means(3 * size_t{markers}, 0);
  for (size_t w = 0; w < windows; ++w) {
    const size_t window_frames = std::min<size_t>(window, frames - w * window);
    const uint32_t length = in.GetVarint("window chunk length");
    if (length < MinimumChunk(uint64_t{window_frames} * markers))
      in.Fail("window chunk length: " + std::to_string(length) + " bytes for " + std::to_string(window_frames) + " frames x " +
              std::to_string(markers) + " markers, under the format's minimum " +
              std::to_string(MinimumChunk(uint64_t{window_frames} * markers)));
    const std::string chunk = in.GetBytes(length, "window chunk");
    try {
      RangeDecoder coder(reinterpret_cast<const uint8_t*>(chunk.data()), chunk.size());
      WindowModels models;
      if (!coder.Bit(models.relative)) std::fill(means.begin(), means.end(), 0);
      for (size_t g = 0; g < group_count; ++g)
        DecodeBlock(coder, models, out.groups[g], window_frames, means, out.blocks[w * group_count + g]);
      if (coder.Consumed() != chunk.size())
        throw std::runtime_error(std::to_string(chunk.size() - coder.Consumed()) + " bytes left after its blocks");
    } catch (const std::runtime_error& error) {
      in.Fail("window " + std::to_string(w) + ": " + error.what());
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
