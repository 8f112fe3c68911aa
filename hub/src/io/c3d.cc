// C3D writer and reader (see c3d.h). Layout: 512-byte blocks; block 1 the header, then the
// parameter section (groups and parameters as linked records), then the point data.
#include "io/c3d.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iterator>
#include <map>
#include <stdexcept>

#include "util/regular_file.h"

namespace mocap {
namespace {

constexpr size_t kBlock = 512;
constexpr uint8_t kKey = 0x50;
constexpr uint8_t kIntel = 84, kDec = 85, kMips = 86;
constexpr size_t kLabelsPerParameter = 255;

// ---- writing the parameter section ----

class ParameterSection {
 public:
  void Group(int8_t id, const std::string& name, const std::string& description) {
    LinkHere();
    bytes_.push_back(static_cast<uint8_t>(name.size()));
    bytes_.push_back(static_cast<uint8_t>(-id));
    Append(name);
    OpenOffset();
    bytes_.push_back(static_cast<uint8_t>(description.size()));
    Append(description);
  }
  // Returns the section offset of the parameter's data (for patching).
  size_t Parameter(int8_t group, const std::string& name, int8_t type, const std::vector<uint8_t>& dims,
                   const std::vector<uint8_t>& data) {
    LinkHere();
    bytes_.push_back(static_cast<uint8_t>(name.size()));
    bytes_.push_back(static_cast<uint8_t>(group));
    Append(name);
    OpenOffset();
    bytes_.push_back(static_cast<uint8_t>(type));
    bytes_.push_back(static_cast<uint8_t>(dims.size()));
    bytes_.insert(bytes_.end(), dims.begin(), dims.end());
    const size_t data_at = bytes_.size();
    bytes_.insert(bytes_.end(), data.begin(), data.end());
    bytes_.push_back(0);  // no description
    return data_at;
  }
  size_t Int16(int8_t group, const std::string& name, const std::vector<uint16_t>& values) {
    std::vector<uint8_t> data;
    for (uint16_t v : values) data.push_back(static_cast<uint8_t>(v & 0xff)), data.push_back(static_cast<uint8_t>(v >> 8));
    return Parameter(group, name, 2, values.size() == 1 ? std::vector<uint8_t>{} : std::vector<uint8_t>{static_cast<uint8_t>(values.size())}, data);
  }
  size_t Float(int8_t group, const std::string& name, float value) {
    std::vector<uint8_t> data(4);
    std::memcpy(data.data(), &value, 4);
    return Parameter(group, name, 4, {}, data);
  }
  void Text(int8_t group, const std::string& name, const std::string& text) {
    Parameter(group, name, -1, {static_cast<uint8_t>(text.size())}, std::vector<uint8_t>(text.begin(), text.end()));
  }
  // A column of strings padded to one width (C3D's 2-D character arrays).
  void Texts(int8_t group, const std::string& name, const std::vector<std::string>& texts) {
    size_t width = 1;
    for (const std::string& t : texts) width = std::max(width, t.size());
    std::vector<uint8_t> data;
    for (const std::string& t : texts) {
      data.insert(data.end(), t.begin(), t.end());
      data.insert(data.end(), width - t.size(), ' ');
    }
    Parameter(group, name, -1, {static_cast<uint8_t>(width), static_cast<uint8_t>(texts.size())}, data);
  }
  // The finished section: 4-byte header, records (the last one's link 0), padded to blocks.
  std::vector<uint8_t> Finish(uint8_t* blocks) {
    std::vector<uint8_t> out = {1, kKey, 0, kIntel};
    out.insert(out.end(), bytes_.begin(), bytes_.end());
    const size_t size = (out.size() + kBlock - 1) / kBlock * kBlock;
    out.resize(size, 0);
    *blocks = static_cast<uint8_t>(size / kBlock);
    out[2] = *blocks;
    return out;
  }
  size_t section_offset(size_t data_at) const { return 4 + data_at; }

 private:
  void Append(const std::string& s) { bytes_.insert(bytes_.end(), s.begin(), s.end()); }
  // Every record's link (bytes from the link itself to the next record) is known once the next
  // record starts; the last record's stays 0, which ends the list.
  void OpenOffset() {
    open_ = bytes_.size();
    bytes_.push_back(0), bytes_.push_back(0);
  }
  void LinkHere() {
    if (open_ == SIZE_MAX) return;
    const size_t link = bytes_.size() - open_;
    bytes_[open_] = static_cast<uint8_t>(link & 0xff);
    bytes_[open_ + 1] = static_cast<uint8_t>(link >> 8);
    open_ = SIZE_MAX;
  }
  std::vector<uint8_t> bytes_;
  size_t open_ = SIZE_MAX;
};

void PutU16(std::vector<uint8_t>& b, size_t word, uint16_t v) {  // 1-based 16-bit word
  b[2 * (word - 1)] = static_cast<uint8_t>(v & 0xff);
  b[2 * (word - 1) + 1] = static_cast<uint8_t>(v >> 8);
}

void PutF32(std::vector<uint8_t>& b, size_t word, float v) { std::memcpy(&b[2 * (word - 1)], &v, 4); }

// ---- reading ----

struct Param {
  int8_t type = 0;
  std::vector<size_t> dims;
  std::vector<uint8_t> data;
};

uint16_t U16(const uint8_t* p) { return static_cast<uint16_t>(p[0] | (p[1] << 8)); }
float F32(const uint8_t* p) {
  float v;
  std::memcpy(&v, p, 4);
  return v;
}

std::string Upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace

// ---- C3dWriter ----

C3dWriter::~C3dWriter() {
  if (file_ != nullptr) std::fclose(file_);
}

void C3dWriter::Fail(const std::string& reason) const { throw std::runtime_error(path_ + ": " + reason); }

void C3dWriter::Open(const std::string& path, const std::vector<std::string>& names, double rate_hz) {
  path_ = path;
  if (names.empty() || names.size() > 32767) Fail("C3D holds 1 to 32767 points, not " + std::to_string(names.size()));
  if (!(rate_hz > 0.0)) Fail("rate must be > 0");
  for (const std::string& n : names)
    if (n.empty() || n.size() > 255) Fail("marker name '" + n + "': 1 to 255 characters");
  num_points_ = names.size();
  ParameterSection params;
  params.Group(1, "POINT", "3-D point parameters");
  params.Int16(1, "USED", {static_cast<uint16_t>(num_points_)});
  params.Float(1, "SCALE", -1.0f);
  params.Float(1, "RATE", static_cast<float>(rate_hz));
  const size_t data_start_at = params.Int16(1, "DATA_START", {0});
  const size_t frames_at = params.Int16(1, "FRAMES", {0});
  const size_t long_frames_at = params.Float(1, "LONG_FRAMES", 0.0f);
  params.Text(1, "UNITS", "mm");
  for (size_t i = 0; i < num_points_; i += kLabelsPerParameter) {
    const std::vector<std::string> chunk(names.begin() + static_cast<long>(i),
                                         names.begin() + static_cast<long>(std::min(num_points_, i + kLabelsPerParameter)));
    const std::string suffix = i == 0 ? "" : std::to_string(i / kLabelsPerParameter + 1);
    params.Texts(1, "LABELS" + suffix, chunk);
    params.Texts(1, "DESCRIPTIONS" + suffix, std::vector<std::string>(chunk.size(), ""));
  }
  params.Group(2, "ANALOG", "analog data parameters");
  params.Int16(2, "USED", {0});
  params.Float(2, "RATE", 0.0f);  // no analog data: 0 samples per point frame (readers check the ratio)
  params.Group(3, "TRIAL", "the capture's frame numbers");
  const size_t start_at = params.Int16(3, "ACTUAL_START_FIELD", {0, 0});
  const size_t end_at = params.Int16(3, "ACTUAL_END_FIELD", {0, 0});
  params.Group(4, "MANUFACTURER", "who wrote the file");
  params.Text(4, "COMPANY", "mocap");
  params.Text(4, "SOFTWARE", "mocap-hub");
  uint8_t blocks = 0;
  std::vector<uint8_t> section = params.Finish(&blocks);
  const uint16_t data_start = static_cast<uint16_t>(2 + blocks);
  const size_t data_start_offset = params.section_offset(data_start_at);
  section[data_start_offset] = static_cast<uint8_t>(data_start & 0xff);
  section[data_start_offset + 1] = static_cast<uint8_t>(data_start >> 8);

  std::vector<uint8_t> header(kBlock, 0);
  header[0] = 2;
  header[1] = kKey;
  PutU16(header, 2, static_cast<uint16_t>(num_points_));
  PutU16(header, 4, 1);                // first frame
  PutF32(header, 7, -1.0f);            // scale: negative = float data
  PutU16(header, 9, data_start);
  PutF32(header, 11, static_cast<float>(rate_hz));

  file_ = std::fopen(path.c_str(), "wb");
  if (file_ == nullptr) Fail("cannot create");
  if (std::fwrite(header.data(), 1, header.size(), file_) != header.size() ||
      std::fwrite(section.data(), 1, section.size(), file_) != section.size())
    Fail("write failed (disk full?)");
  patch_frames_int16_ = {static_cast<long>(2 * (5 - 1)), static_cast<long>(kBlock + params.section_offset(frames_at))};
  patch_long_frames_ = static_cast<long>(kBlock + params.section_offset(long_frames_at));
  patch_start_field_ = static_cast<long>(kBlock + params.section_offset(start_at));
  patch_end_field_ = static_cast<long>(kBlock + params.section_offset(end_at));
  row_.assign(num_points_ * 4, 0.0f);
  frames_ = 0;
}

void C3dWriter::WriteRow(const Eigen::Vector3d* points, const float* residuals) {
  for (size_t i = 0; i < num_points_; ++i) {
    const bool gap = points == nullptr || MarkerTrajectories::IsGap(points[i]);
    row_[4 * i + 0] = gap ? 0.0f : static_cast<float>(points[i].x());
    row_[4 * i + 1] = gap ? 0.0f : static_cast<float>(points[i].y());
    row_[4 * i + 2] = gap ? 0.0f : static_cast<float>(points[i].z());
    row_[4 * i + 3] = gap ? -1.0f : residuals != nullptr ? residuals[i] : 0.0f;
  }
  if (std::fwrite(row_.data(), sizeof(float), row_.size(), file_) != row_.size()) Fail("write failed (disk full?)");
  ++frames_;
}

void C3dWriter::WriteFrame(uint64_t frame_number, const Eigen::Vector3d* points, size_t count, const float* residuals) {
  if (file_ == nullptr) Fail("not open");
  if (count != num_points_) Fail("frame with " + std::to_string(count) + " points, file has " + std::to_string(num_points_));
  if (frames_ == 0) {
    first_frame_ = frame_number;
  } else {
    if (frame_number < next_frame_) Fail("frame numbers must increase");
    if (frame_number - next_frame_ > kMaxSkippedFrames)
      Fail("frame " + std::to_string(frame_number) + " is " + std::to_string(frame_number - next_frame_) +
           " frames past the last one (at most " + std::to_string(kMaxSkippedFrames) + " are filled with gaps)");
    while (next_frame_ < frame_number) WriteRow(nullptr, nullptr), ++next_frame_;
  }
  WriteRow(points, residuals);
  next_frame_ = frame_number + 1;
}

void C3dWriter::Close() {
  if (file_ == nullptr) return;
  auto patch = [this](long offset, const void* data, size_t size) {
    if (std::fseek(file_, offset, SEEK_SET) != 0 || std::fwrite(data, 1, size, file_) != size) Fail("cannot patch the frame count");
  };
  const uint16_t frames16 = static_cast<uint16_t>(std::min<uint64_t>(frames_, 65535));
  const uint8_t f16[2] = {static_cast<uint8_t>(frames16 & 0xff), static_cast<uint8_t>(frames16 >> 8)};
  for (long offset : patch_frames_int16_) patch(offset, f16, 2);  // header's last frame = count (first is 1)
  const float long_frames = static_cast<float>(frames_);
  patch(patch_long_frames_, &long_frames, 4);
  auto field = [&](long offset, uint64_t frame_number) {
    const uint64_t f = frame_number + 1;  // C3D fields are 1-based
    const uint8_t words[4] = {static_cast<uint8_t>(f & 0xff), static_cast<uint8_t>((f >> 8) & 0xff),
                              static_cast<uint8_t>((f >> 16) & 0xff), static_cast<uint8_t>((f >> 24) & 0xff)};
    patch(offset, words, 4);
  };
  if (frames_ > 0) {
    field(patch_start_field_, first_frame_);
    field(patch_end_field_, next_frame_ - 1);
  }
  const bool ok = std::fclose(file_) == 0;
  file_ = nullptr;
  if (!ok) Fail("write failed (disk full?)");
}

void WriteC3d(const MarkerTrajectories& trajectories, const std::string& path, const std::vector<float>* residuals) {
  if (residuals != nullptr && residuals->size() != trajectories.points.size())
    throw std::invalid_argument(path + ": " + std::to_string(residuals->size()) + " residuals for " +
                                std::to_string(trajectories.points.size()) + " points");
  C3dWriter writer;
  writer.Open(path, trajectories.names, trajectories.rate_hz);
  for (size_t f = 0; f < trajectories.NumFrames(); ++f)
    writer.WriteFrame(trajectories.frame_numbers[f], &trajectories.points[f * trajectories.NumMarkers()],
                      trajectories.NumMarkers(), residuals ? &(*residuals)[f * trajectories.NumMarkers()] : nullptr);
  writer.Close();
}

// ---- reader ----

namespace {

[[noreturn]] void Refuse(const std::string& source, const std::string& reason) {
  throw std::runtime_error(source + ": " + reason);
}

// The parameter section: groups by id, parameters by (group id, name).
struct C3dParameters {
  std::map<int, std::string> groups;
  std::map<std::pair<int, std::string>, Param> params;

  const Param* Find(const std::string& group, const std::string& name) const {
    for (const auto& [id, g] : groups) {
      if (g != group) continue;
      auto it = params.find({id, name});
      if (it != params.end()) return &it->second;
    }
    return nullptr;
  }
  double Number(const std::string& group, const std::string& name, double fallback) const {
    const Param* p = Find(group, name);
    if (p == nullptr || p->data.empty()) return fallback;
    if (p->type == 2 && p->data.size() >= 2) return static_cast<double>(U16(p->data.data()));
    if (p->type == 4 && p->data.size() >= 4) return static_cast<double>(F32(p->data.data()));
    if (p->type == 1) return static_cast<double>(p->data[0]);
    return fallback;
  }
};

// One parameter record's type, dimensions and data from `p` (just past its name and link).
Param ReadParameter(const std::vector<uint8_t>& bytes, size_t p, size_t param_end, const std::string& name,
                    const std::string& source) {
  if (p + 2 > param_end) Refuse(source, "parameter " + name + " truncated");
  Param param;
  param.type = static_cast<int8_t>(bytes[p]);
  const size_t ndims = bytes[p + 1];
  p += 2;
  if (param.type != -1 && param.type != 1 && param.type != 2 && param.type != 4)
    Refuse(source, "parameter " + name + " has type " + std::to_string(param.type));
  if (p + ndims > param_end) Refuse(source, "parameter " + name + " truncated");
  size_t count = 1;
  for (size_t d = 0; d < ndims; ++d) param.dims.push_back(bytes[p + d]), count *= bytes[p + d];
  p += ndims;
  const size_t size = count * static_cast<size_t>(std::abs(param.type));
  if (p + size > param_end) Refuse(source, "parameter " + name + " data past the end of the section");
  param.data.assign(bytes.begin() + static_cast<long>(p), bytes.begin() + static_cast<long>(p + size));
  return param;
}

C3dParameters ReadParameterSection(const std::vector<uint8_t>& bytes, const std::string& source) {
  const size_t param_at = (size_t{bytes[0]} - 1) * kBlock;
  if (param_at + 4 > bytes.size()) Refuse(source, "parameter section past the end of the file");
  const uint8_t processor = bytes[param_at + 3];
  if (processor == kDec || processor == kMips)
    Refuse(source, std::string(processor == kDec ? "DEC" : "MIPS (big-endian)") +
                       " C3D files are not supported; convert to Intel");
  if (processor != kIntel) Refuse(source, "unknown processor type " + std::to_string(processor));
  const size_t param_end = std::min(bytes.size(), param_at + std::max<size_t>(1, bytes[param_at + 2]) * kBlock);
  C3dParameters section;
  for (size_t pos = param_at + 4; pos + 2 <= param_end;) {
    const int name_len = std::abs(static_cast<int8_t>(bytes[pos]));
    const int id = static_cast<int8_t>(bytes[pos + 1]);
    if (name_len == 0 || id == 0) break;
    const size_t name_at = pos + 2, link_at = name_at + static_cast<size_t>(name_len);
    if (link_at + 2 > param_end) Refuse(source, "parameter record past the end of the section");
    const std::string name = Upper(std::string(reinterpret_cast<const char*>(&bytes[name_at]), static_cast<size_t>(name_len)));
    const uint16_t link = U16(&bytes[link_at]);
    if (id < 0) {
      section.groups[-id] = name;
    } else {
      section.params[{id, name}] = ReadParameter(bytes, link_at + 2, param_end, name, source);
    }
    if (link == 0) break;
    pos = link_at + link;
  }
  return section;
}

// POINT:LABELS, LABELS2, ... (each at most 255 names); unnamed points get default names.
std::vector<std::string> PointLabels(const C3dParameters& section, size_t points) {
  std::vector<std::string> names;
  for (size_t chunk = 0; names.size() < points; ++chunk) {
    const Param* labels = section.Find("POINT", chunk == 0 ? "LABELS" : "LABELS" + std::to_string(chunk + 1));
    if (labels == nullptr || labels->type != -1 || labels->dims.size() != 2 || labels->dims[1] == 0) break;
    const size_t width = labels->dims[0];
    for (size_t i = 0; i < labels->dims[1] && names.size() < points; ++i) {
      // Labels of width 0 hold no bytes at all: no name to read (and no element to point at).
      std::string name = width == 0 ? std::string()
                                     : std::string(reinterpret_cast<const char*>(&labels->data[i * width]), width);
      name.erase(name.find_last_not_of(" \0", std::string::npos, 2) + 1);
      names.push_back(name.empty() ? DefaultMarkerName(names.size()) : name);
    }
  }
  while (names.size() < points) names.push_back(DefaultMarkerName(names.size()));
  return names;
}

// How the point data is laid out, from the header and the POINT group.
struct PointLayout {
  size_t points = 0;
  double scale = 1.0;   // negative: floats
  size_t value_size = 2;
  size_t frame_size = 0;  // bytes per frame, analog samples included
  size_t data_at = 0;
  size_t frames = 0;      // what the header promises, cut to what the file holds
  uint64_t first = 0;     // frame number of the first row
};

PointLayout ReadPointLayout(const std::vector<uint8_t>& bytes, const C3dParameters& section, double* rate,
                            const std::string& source) {
  const uint8_t* h = bytes.data();
  // USED and DATA_START are 16-bit counts in the format; a parameter may still hold them as a
  // float of any size (converting one past size_t is undefined, and a huge USED would name
  // that many markers): out of range is refused.
  const auto count16 = [&](const char* name, double value) {
    if (!(value >= 0.0 && value <= 65535.0)) Refuse(source, std::string("POINT:") + name + " out of range");
    return static_cast<size_t>(value);
  };
  PointLayout layout;
  layout.points = count16("USED", section.Number("POINT", "USED", U16(h + 2)));
  layout.scale = section.Number("POINT", "SCALE", F32(h + 12));
  *rate = section.Number("POINT", "RATE", F32(h + 20));
  const size_t data_start = count16("DATA_START", section.Number("POINT", "DATA_START", U16(h + 16)));
  if (!(*rate > 0.0) || !std::isfinite(*rate)) Refuse(source, "no usable POINT:RATE");
  if (!std::isfinite(layout.scale) || layout.scale == 0.0) Refuse(source, "no usable POINT:SCALE");
  if (data_start == 0) Refuse(source, "no usable POINT:DATA_START");
  const size_t analog_per_frame = U16(h + 4);  // analog samples of all channels per 3-D frame
  layout.value_size = layout.scale < 0.0 ? 4 : 2;
  layout.frame_size = (layout.points * 4 + analog_per_frame) * layout.value_size;
  layout.data_at = (data_start - 1) * kBlock;
  if (layout.data_at > bytes.size()) Refuse(source, "POINT:DATA_START past the end of the file");
  double declared = section.Number("POINT", "LONG_FRAMES", -1.0);
  if (!(declared >= 0.0)) declared = section.Number("POINT", "FRAMES", static_cast<double>(U16(h + 8)) - U16(h + 6) + 1);
  // A file cut short (a writer that crashed) keeps the frames it has; no promise in the header
  // makes the reader allocate more than the file holds (compared as doubles: a float LONG_FRAMES
  // may be past any size_t).
  const size_t held = layout.frame_size > 0 ? (bytes.size() - layout.data_at) / layout.frame_size : 0;
  layout.frames = declared > 0.0 ? (declared < static_cast<double>(held) ? static_cast<size_t>(declared) : held) : 0;
  layout.first = U16(h + 6) > 0 ? U16(h + 6) - 1u : 0u;
  if (const Param* start = section.Find("TRIAL", "ACTUAL_START_FIELD"); start && start->type == 2 && start->data.size() >= 4) {
    const uint64_t field = U16(start->data.data()) | (uint64_t{U16(start->data.data() + 2)} << 16);
    if (field > 0) layout.first = field - 1;
  }
  return layout;
}

void ReadPointFrames(const std::vector<uint8_t>& bytes, const PointLayout& layout, MarkerTrajectories* out,
                     std::vector<float>* residuals) {
  const bool floats = layout.scale < 0.0;
  out->points.reserve(layout.frames * layout.points);
  if (residuals) residuals->assign(layout.frames * layout.points, -1.0f);
  for (size_t f = 0; f < layout.frames; ++f) {
    const size_t i = out->AddFrame(layout.first + f);
    const uint8_t* row = &bytes[layout.data_at + f * layout.frame_size];
    for (size_t m = 0; m < layout.points; ++m) {
      double v[4];
      for (int k = 0; k < 4; ++k) {
        const uint8_t* p = row + (m * 4 + static_cast<size_t>(k)) * layout.value_size;
        v[k] = floats ? static_cast<double>(F32(p)) : static_cast<double>(static_cast<int16_t>(U16(p)));
      }
      if (v[3] < 0.0) continue;  // the residual word says: no point here
      const double s = floats ? 1.0 : layout.scale;
      const Eigen::Vector3d point(v[0] * s, v[1] * s, v[2] * s);
      if (!point.allFinite()) continue;
      out->At(i, m) = point;
      if (residuals) (*residuals)[i * layout.points + m] = static_cast<float>(v[3]);
    }
  }
}

}  // namespace

MarkerTrajectories ParseC3d(const std::vector<uint8_t>& bytes, const std::string& source, std::vector<float>* residuals) {
  if (bytes.size() < kBlock) Refuse(source, "too short for a C3D header (" + std::to_string(bytes.size()) + " bytes)");
  if (bytes[1] != kKey || bytes[0] == 0) Refuse(source, "not a C3D file (no 0x50 key in the header)");
  const C3dParameters section = ReadParameterSection(bytes, source);
  MarkerTrajectories out;
  const PointLayout layout = ReadPointLayout(bytes, section, &out.rate_hz, source);
  out.names = PointLabels(section, layout.points);
  ReadPointFrames(bytes, layout, &out, residuals);
  return out;
}

MarkerTrajectories ReadC3d(const std::string& path, std::vector<float>* residuals) {
  const std::string text = ReadRegularFile(path, kMaxRecordingFileBytes, "a C3D file");
  return ParseC3d(std::vector<uint8_t>(text.begin(), text.end()), path, residuals);
}

}  // namespace mocap
