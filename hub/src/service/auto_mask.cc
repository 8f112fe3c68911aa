// Static-reflection masks: persistent blobs -> regions -> node commands and JSON (see auto_mask.h).
#include "service/auto_mask.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>
#include <type_traits>

#include <nlohmann/json.hpp>

#include "wire/limits.h"

namespace mocap::service {
namespace {

constexpr double kPi = 3.14159265358979323846;

// One blob followed across frames. The first pass finds where it is (its mean centroid); the
// second counts the steady sightings, those that stay near that mean: a reflection's centroid
// only jitters (apart from the odd frame a marker passing by merges with it), while a marker
// creeping through the view is followed by one candidate whose sightings spread out.
struct Candidate {
  double sum_x = 0.0, sum_y = 0.0;
  size_t sightings = 0;
  size_t steady_frames = 0;
  size_t last_steady_frame = SIZE_MAX;
  double min_x = 0.0, max_x = 0.0, min_y = 0.0, max_y = 0.0;  // steady centroids' spread
  double max_radius = 0.0;                                    // of the steady sightings
  double x() const { return sum_x / sightings; }
  double y() const { return sum_y / sightings; }
};

// Candidates bucketed by match-radius cells, so a blob is compared with its neighbours only.
class CandidateIndex {
 public:
  explicit CandidateIndex(double cell) : cell_(cell) {}
  // The nearest candidate within radius of (x, y), or SIZE_MAX.
  size_t Nearest(const std::vector<Candidate>& all, double x, double y, double radius) const {
    size_t best = SIZE_MAX;
    double best_d = radius;
    const auto [cx, cy] = Cell(x, y);
    for (int64_t dy = -2; dy <= 2; ++dy) {
      for (int64_t dx = -2; dx <= 2; ++dx) {
        auto it = cells_.find({cx + dx, cy + dy});
        if (it == cells_.end()) continue;
        for (size_t i : it->second) {
          const double d = std::hypot(all[i].x() - x, all[i].y() - y);
          if (d <= best_d) best_d = d, best = i;
        }
      }
    }
    return best;
  }
  // A candidate stays filed under the cell of its first sighting; searching two cells around
  // a blob still finds it while its mean drifts less than one match radius from there.
  void Insert(size_t i, double x, double y) { cells_[Cell(x, y)].push_back(i); }

 private:
  std::pair<int64_t, int64_t> Cell(double x, double y) const {
    return {static_cast<int64_t>(std::floor(x / cell_)), static_cast<int64_t>(std::floor(y / cell_))};
  }
  double cell_;
  std::map<std::pair<int64_t, int64_t>, std::vector<size_t>> cells_;
};

bool Overlap(const MaskRect& a, const MaskRect& b) {
  return a.x < b.x + b.width && b.x < a.x + a.width && a.y < b.y + b.height && b.y < a.y + a.height;
}

MaskRect Union(const MaskRect& a, const MaskRect& b) {
  const uint32_t x0 = std::min(a.x, b.x), y0 = std::min(a.y, b.y);
  const uint32_t x1 = std::max(a.x + a.width, b.x + b.width), y1 = std::max(a.y + a.height, b.y + b.height);
  return {x0, y0, x1 - x0, y1 - y0};
}

// Merges overlapping rectangles until none overlap (the node ORs them anyway; fewer rectangles
// fit its limit more often).
std::vector<MaskRect> MergeOverlaps(std::vector<MaskRect> rects) {
  for (bool merged = true; merged;) {
    merged = false;
    for (size_t i = 0; i < rects.size() && !merged; ++i) {
      for (size_t j = i + 1; j < rects.size(); ++j) {
        if (!Overlap(rects[i], rects[j])) continue;
        rects[i] = Union(rects[i], rects[j]);
        rects.erase(rects.begin() + static_cast<std::ptrdiff_t>(j));
        merged = true;
        break;
      }
    }
  }
  std::sort(rects.begin(), rects.end(), [](const MaskRect& a, const MaskRect& b) {
    return a.y != b.y ? a.y < b.y : a.x < b.x;
  });
  return rects;
}

// Pixels whose square [i - 0.5, i + 0.5] meets [lo, hi], clipped to [0, size).
bool PixelSpan(double lo, double hi, uint32_t size, uint32_t* first, uint32_t* count) {
  const double a = std::max(0.0, std::floor(lo + 0.5));
  const double b = std::min(static_cast<double>(size) - 1.0, std::floor(hi + 0.5));
  if (b < a) return false;
  *first = static_cast<uint32_t>(a);
  *count = static_cast<uint32_t>(b - a) + 1;
  return true;
}

template <typename T>
T Field(const nlohmann::json& j, const char* name, const std::string& where) {
  if (!j.is_object() || !j.contains(name)) throw std::runtime_error(where + ": missing \"" + name + "\"");
  if constexpr (std::is_integral_v<T>) {
    // nlohmann's get<integer>() converts floats and negative numbers too: a float past the
    // type's range ("width": 1e71) is undefined behaviour, a negative one wraps ("camera_id": -1
    // became camera 4294967295). Only integers the type holds are taken.
    const nlohmann::json& v = j.at(name);
    const bool fits = v.is_number_unsigned()
                          ? v.get<uint64_t>() <= static_cast<uint64_t>(std::numeric_limits<T>::max())
                          : v.is_number_integer() && v.get<int64_t>() >= static_cast<int64_t>(std::numeric_limits<T>::min()) &&
                                (v.get<int64_t>() < 0 || static_cast<uint64_t>(v.get<int64_t>()) <=
                                                             static_cast<uint64_t>(std::numeric_limits<T>::max()));
    if (v.is_number() && !fits)
      throw std::runtime_error(where + ": \"" + name + "\" must be an integer from " +
                               std::to_string(std::numeric_limits<T>::min()) + " to " +
                               std::to_string(std::numeric_limits<T>::max()) + ", not " + v.dump());
  }
  try {
    return j.at(name).get<T>();
  } catch (const nlohmann::json::exception&) {
    throw std::runtime_error(where + ": \"" + name + "\" has the wrong type");
  }
}

}  // namespace

std::string AutoMaskOptions::Check() const {
  if (min_frames == 0) return "min_frames must be > 0";
  if (!(min_presence > 0.0 && min_presence <= 1.0)) return "min_presence must be in (0, 1]";
  if (!(match_radius_px > 0.0)) return "match_radius_px must be > 0";
  if (!(steady_radius_px > 0.0)) return "steady_radius_px must be > 0";
  if (!(margin_px >= 0.0) || !(margin_per_radius >= 0.0)) return "margins must be >= 0";
  if (max_candidates == 0) return "max_candidates must be > 0";
  return {};
}

CameraMask ComputeAutoMask(const std::vector<CameraFrame>& frames, const AutoMaskOptions& options) {
  const std::string problem = options.Check();
  if (!problem.empty()) throw std::invalid_argument("auto mask: " + problem);
  if (frames.size() < options.min_frames)
    throw std::invalid_argument("auto mask: " + std::to_string(frames.size()) + " frames, at least " +
                                std::to_string(options.min_frames) + " needed");
  CameraMask mask;
  mask.camera_id = frames.front().camera_id;
  mask.width = frames.front().width;
  mask.height = frames.front().height;
  mask.frames = frames.size();
  if (mask.width == 0 || mask.height == 0) throw std::invalid_argument("auto mask: frame without image size");
  std::vector<Candidate> candidates;
  CandidateIndex index(options.match_radius_px);
  for (size_t f = 0; f < frames.size(); ++f) {
    const CameraFrame& frame = frames[f];
    if (frame.camera_id != mask.camera_id || frame.width != mask.width || frame.height != mask.height)
      throw std::invalid_argument("auto mask: frames of more than one camera or image size");
    for (const Blob& blob : frame.blobs) {
      const double x = blob.pixel.x(), y = blob.pixel.y();
      size_t i = index.Nearest(candidates, x, y, options.match_radius_px);
      if (i == SIZE_MAX) {
        if (candidates.size() >= options.max_candidates) continue;
        i = candidates.size();
        candidates.emplace_back();
        index.Insert(i, x, y);
      }
      candidates[i].sum_x += x;
      candidates[i].sum_y += y;
      ++candidates[i].sightings;
    }
  }
  for (size_t f = 0; f < frames.size(); ++f) {
    for (const Blob& blob : frames[f].blobs) {
      const double x = blob.pixel.x(), y = blob.pixel.y();
      const size_t i = index.Nearest(candidates, x, y, options.steady_radius_px);
      if (i == SIZE_MAX) continue;
      Candidate& c = candidates[i];
      if (c.steady_frames == 0) c.min_x = c.max_x = x, c.min_y = c.max_y = y;
      c.min_x = std::min(c.min_x, x), c.max_x = std::max(c.max_x, x);
      c.min_y = std::min(c.min_y, y), c.max_y = std::max(c.max_y, y);
      c.max_radius = std::max(c.max_radius, std::sqrt(blob.area / kPi));
      if (c.last_steady_frame != f) ++c.steady_frames, c.last_steady_frame = f;
    }
  }
  std::vector<MaskRect> regions;
  for (const Candidate& c : candidates) {
    const double presence = static_cast<double>(c.steady_frames) / static_cast<double>(frames.size());
    if (presence < options.min_presence) continue;
    mask.blobs.push_back({c.x(), c.y(), c.max_radius, presence});
    const double reach = c.max_radius * (1.0 + options.margin_per_radius) + options.margin_px;
    MaskRect r;
    if (PixelSpan(c.min_x - reach, c.max_x + reach, mask.width, &r.x, &r.width) &&
        PixelSpan(c.min_y - reach, c.max_y + reach, mask.height, &r.y, &r.height))
      regions.push_back(r);
  }
  std::sort(mask.blobs.begin(), mask.blobs.end(), [](const StaticBlob& a, const StaticBlob& b) {
    return a.y != b.y ? a.y < b.y : a.x < b.x;
  });
  mask.regions = MergeOverlaps(std::move(regions));
  return mask;
}

MaskBits RasteriseMask(const CameraMask& mask, const NodeMaskLimits& limits) {
  const uint64_t bits_per_chunk = uint64_t{limits.chunk_bytes} * 8;
  for (uint32_t cell = 1; cell <= wire::kMaxImageSide; ++cell) {
    const uint64_t cx = (mask.width + cell - 1) / cell, cy = (mask.height + cell - 1) / cell;
    if (cx * cy > limits.max_cells || (cx * cy + bits_per_chunk - 1) / bits_per_chunk > limits.max_chunks)
      continue;
    MaskBits out;
    out.cell_px = cell;
    out.cells_x = static_cast<uint32_t>(cx);
    out.cells_y = static_cast<uint32_t>(cy);
    out.bits.assign((cx * cy + 7) / 8, 0);
    for (const MaskRect& r : mask.regions) {
      for (uint64_t y = r.y / cell; y <= (uint64_t{r.y} + r.height - 1) / cell; ++y) {
        for (uint64_t x = r.x / cell; x <= (uint64_t{r.x} + r.width - 1) / cell; ++x) {
          const uint64_t bit = y * cx + x;
          out.bits[bit >> 3] |= static_cast<uint8_t>(1u << (bit & 7));
        }
      }
    }
    return out;
  }
  throw std::invalid_argument("auto mask: no cell size fits the node's mask limits");
}

std::vector<v1::Control> MaskCommands(const CameraMask& mask, const NodeMaskLimits& limits) {
  std::vector<v1::Control> commands;
  if (mask.regions.empty()) {
    commands.emplace_back().mutable_set_mask()->set_clear(true);
    return commands;
  }
  if (mask.regions.size() <= limits.max_rects) {
    v1::SetMask* m = commands.emplace_back().mutable_set_mask();
    for (const MaskRect& r : mask.regions) {
      v1::Rect* out = m->add_rects();
      out->set_x(r.x);
      out->set_y(r.y);
      out->set_width(r.width);
      out->set_height(r.height);
    }
    return commands;
  }
  const MaskBits bits = RasteriseMask(mask, limits);
  const size_t chunks = (bits.bits.size() + limits.chunk_bytes - 1) / limits.chunk_bytes;
  for (size_t i = 0; i < chunks; ++i) {
    v1::SetMask* m = commands.emplace_back().mutable_set_mask();
    m->set_cell_px(bits.cell_px);
    m->set_cells_x(bits.cells_x);
    m->set_cells_y(bits.cells_y);
    m->set_chunk_index(static_cast<uint32_t>(i));
    m->set_chunk_count(static_cast<uint32_t>(chunks));
    m->set_bit_offset(static_cast<uint32_t>(i * limits.chunk_bytes * 8));
    const size_t begin = i * limits.chunk_bytes;
    const size_t end = std::min(bits.bits.size(), begin + limits.chunk_bytes);
    m->set_bits(std::string(bits.bits.begin() + static_cast<std::ptrdiff_t>(begin),
                            bits.bits.begin() + static_cast<std::ptrdiff_t>(end)));
  }
  return commands;
}

size_t CountMaskedCameras(const std::vector<CameraMask>& masks, const Rig& rig) {
  size_t count = 0;
  for (const CameraMask& m : masks)
    count += !m.regions.empty() && (rig.cameras.empty() || rig.Find(m.camera_id) != nullptr);
  return count;
}

nlohmann::json MasksToJson(const std::vector<CameraMask>& masks) {
  nlohmann::json cameras = nlohmann::json::array();
  for (const CameraMask& m : masks) {
    nlohmann::json blobs = nlohmann::json::array(), regions = nlohmann::json::array();
    for (const StaticBlob& b : m.blobs)
      blobs.push_back({{"x", b.x}, {"y", b.y}, {"radius_px", b.radius_px}, {"presence", b.presence}});
    for (const MaskRect& r : m.regions)
      regions.push_back({{"x", r.x}, {"y", r.y}, {"width", r.width}, {"height", r.height}});
    cameras.push_back({{"camera_id", m.camera_id}, {"width", m.width}, {"height", m.height},
                       {"frames", m.frames}, {"blobs", blobs}, {"regions", regions}});
  }
  return {{"version", 1}, {"cameras", cameras}};
}

std::vector<CameraMask> MasksFromJson(const nlohmann::json& document, const std::string& source) {
  if (Field<int>(document, "version", source) != 1) throw std::runtime_error(source + ": unsupported version");
  const nlohmann::json cameras = Field<nlohmann::json>(document, "cameras", source);
  if (!cameras.is_array()) throw std::runtime_error(source + ": \"cameras\" must be an array");
  std::vector<CameraMask> out;
  std::set<uint32_t> ids;
  for (const nlohmann::json& c : cameras) {
    const std::string where = source + ": camera " + std::to_string(out.size());
    CameraMask m;
    m.camera_id = Field<uint32_t>(c, "camera_id", where);
    m.width = Field<uint32_t>(c, "width", where);
    m.height = Field<uint32_t>(c, "height", where);
    m.frames = c.contains("frames") ? Field<size_t>(c, "frames", where) : 0;
    if (m.camera_id == 0 || !ids.insert(m.camera_id).second)
      throw std::runtime_error(where + ": camera_id must be unique and > 0");
    if (m.width == 0 || m.height == 0 || m.width > wire::kMaxImageSide || m.height > wire::kMaxImageSide)
      throw std::runtime_error(where + ": image size out of range");
    if (c.contains("blobs")) {
      for (const nlohmann::json& b : Field<nlohmann::json>(c, "blobs", where))
        m.blobs.push_back({Field<double>(b, "x", where), Field<double>(b, "y", where),
                           Field<double>(b, "radius_px", where), Field<double>(b, "presence", where)});
    }
    for (const nlohmann::json& r : Field<nlohmann::json>(c, "regions", where)) {
      MaskRect rect{Field<uint32_t>(r, "x", where), Field<uint32_t>(r, "y", where),
                    Field<uint32_t>(r, "width", where), Field<uint32_t>(r, "height", where)};
      if (rect.width == 0 || rect.height == 0 || uint64_t{rect.x} + rect.width > m.width ||
          uint64_t{rect.y} + rect.height > m.height)
        throw std::runtime_error(where + ": region outside the image");
      m.regions.push_back(rect);
    }
    out.push_back(std::move(m));
  }
  return out;
}

}  // namespace mocap::service
