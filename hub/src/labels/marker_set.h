// A marker set (labelling template, as QTM's AIM models and Vicon's labelling skeletons): the
// marker names, each marker's place in a mean body shape, the distances between every pair of
// markers seen together (mean, sd, min, max over the training frames) and the segments: rigid-ish
// clusters of markers whose mutual distances barely change. Kept as JSON, editable by hand:
//   {"version": 1, "type": "marker-set",
//    "markers": [{"name": "R.ASIS", "mean": [x, y, z]}, ...],     // mean shape, mm, +z up
//    "segments": [["R.ASIS", "L.ASIS", "V.Sacral"], ...],
//    "distances": [{"a": "R.ASIS", "b": "L.ASIS", "mean": 261.1, "sd": 0.7, "min": 259.4,
//                   "max": 263.0, "frames": 151}, ...]}
// A marker never seen in training has a null "mean" and takes no part in the shape.
// Errors: std::runtime_error "<source>: <reason>" for files (the io layer's rule). Pure apart from
// the file functions.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json_fwd.hpp>

namespace mocap {

struct MarkerDistance {
  int a = 0, b = 0;  // marker indices, a < b
  double mean = 0.0, sd = 0.0, min = 0.0, max = 0.0;
  size_t frames = 0;
};

struct MarkerSet {
  std::vector<std::string> names;
  std::vector<Eigen::Vector3d> mean_shape;  // per marker, mm, +z up, origin at the centroid; NaN: unknown
  std::vector<std::vector<int>> segments;   // marker indices; a marker is in one segment at most
  std::vector<MarkerDistance> distances;

  size_t NumMarkers() const { return names.size(); }
  // Index of a name, -1 when not in the set.
  int Find(const std::string& name) const;
  // The segment holding `marker`, -1 when none.
  int SegmentOf(int marker) const;
  // Distance statistics of a pair, nullptr when never seen together.
  const MarkerDistance* Distance(int a, int b) const;
  // Rebuilds the lookup tables after the vectors above were changed.
  void Index();

 private:
  std::vector<int> segment_of_;
  std::vector<int> distance_index_;  // a * n + b -> index into distances, -1
};

// Limits of the reader: a set larger than this is refused (memory stays bounded).
constexpr size_t kMaxMarkerSetMarkers = 1000;

nlohmann::json MarkerSetToJson(const MarkerSet& set);
MarkerSet MarkerSetFromJson(const nlohmann::json& document, const std::string& source);
MarkerSet ReadMarkerSetFile(const std::string& path);
void WriteMarkerSetFile(const MarkerSet& set, const std::string& path);

}  // namespace mocap
