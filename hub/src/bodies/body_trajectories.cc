// Rigid bodies over a whole recording (see body_trajectories.h).
#include "bodies/body_trajectories.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "util/regular_file.h"

namespace mocap {

std::vector<BodyPoseRow> TrackBodies(const MarkerTrajectories& markers, const std::vector<RigidBodyDefinition>& bodies,
                                     const BodyTrackerOptions& options, const BodySmoothingOptions& smoothing,
                                     std::vector<BodySmoothingStats>* stats) {
  smoothing.Check();
  BodyTracker tracker(bodies, options);
  std::vector<BodyPoseRow> rows(markers.NumFrames());
  // Per body and frame the markers fitted and their points, for the smoothing.
  std::vector<std::vector<BodyFrameMarkers>> fitted(bodies.size(), std::vector<BodyFrameMarkers>(markers.NumFrames()));
  std::vector<Eigen::Vector3d> points;
  for (size_t f = 0; f < markers.NumFrames(); ++f) {
    points.clear();
    for (size_t m = 0; m < markers.NumMarkers(); ++m)
      if (markers.Has(f, m)) points.push_back(markers.At(f, m));
    rows[f].frame_number = markers.frame_numbers[f];
    rows[f].poses = tracker.Update(points);
    for (size_t b = 0; b < bodies.size(); ++b) {
      const BodyPose& pose = rows[f].poses[b];
      if (!pose.tracked) continue;
      for (size_t i = 0; i < pose.point_of_marker.size(); ++i) {
        const int p = pose.point_of_marker[i];
        if (p < 0) continue;
        fitted[b][f].in_body.push_back(bodies[b].markers[i]);
        fitted[b][f].in_world.push_back(points[static_cast<size_t>(p)]);
      }
    }
  }
  if (stats) stats->assign(bodies.size(), {});
  std::vector<BodyPose> poses(markers.NumFrames());
  for (size_t b = 0; b < bodies.size(); ++b) {
    for (size_t f = 0; f < rows.size(); ++f) poses[f] = std::move(rows[f].poses[b]);
    const BodySmoothingStats s = SmoothBodyPoses(bodies[b], fitted[b], &poses, smoothing);
    if (stats) (*stats)[b] = s;
    for (size_t f = 0; f < rows.size(); ++f) rows[f].poses[b] = std::move(poses[f]);
  }
  return rows;
}

void AddVirtualMarkers(MarkerTrajectories* markers, const std::vector<RigidBodyDefinition>& bodies,
                       const std::vector<BodyPoseRow>& rows) {
  MarkerTrajectories out;
  out.rate_hz = markers->rate_hz;
  out.names = markers->names;
  for (const RigidBodyDefinition& b : bodies) out.names.push_back(b.name);
  for (size_t f = 0; f < markers->NumFrames(); ++f) {
    const size_t i = out.AddFrame(markers->frame_numbers[f]);
    for (size_t m = 0; m < markers->NumMarkers(); ++m) out.At(i, m) = markers->At(f, m);
    for (size_t b = 0; b < bodies.size(); ++b) {
      const BodyPose& pose = rows[f].poses[b];
      if (pose.tracked || pose.predicted) out.At(i, markers->NumMarkers() + b) = pose.pivot;
    }
  }
  *markers = std::move(out);
}

void WriteBodyPoses(const std::string& path, const std::vector<RigidBodyDefinition>& bodies,
                    const std::vector<BodyPoseRow>& rows, double rate_hz) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "w"), &std::fclose);
  if (!file) throw std::runtime_error(path + ": cannot create");
  std::fputs("frame\ttime_s\tbody\ttracked\tpredicted\tx\ty\tz\tqx\tqy\tqz\tqw\tmean_error_mm\tmarkers\n", file.get());
  for (const BodyPoseRow& row : rows)
    for (size_t b = 0; b < bodies.size(); ++b) {
      const BodyPose& p = row.poses[b];
      const Eigen::Quaterniond& q = p.orientation;
      std::fprintf(file.get(), "%llu\t%.6f\t%s\t%d\t%d\t", static_cast<unsigned long long>(row.frame_number + 1),
                   static_cast<double>(row.frame_number) / rate_hz, bodies[b].name.c_str(), p.tracked ? 1 : 0,
                   p.predicted ? 1 : 0);
      // A frame without a pose leaves its cells empty (no zeros and identity a reader could take for one).
      if (p.tracked || p.predicted)
        std::fprintf(file.get(), "%.3f\t%.3f\t%.3f\t%.6f\t%.6f\t%.6f\t%.6f\t%.3f\t%zu\n", p.pivot.x(), p.pivot.y(),
                     p.pivot.z(), q.x(), q.y(), q.z(), q.w(), p.mean_error_mm, p.markers);
      else
        std::fprintf(file.get(), "\t\t\t\t\t\t\t\t%zu\n", p.markers);
    }
  if (std::fflush(file.get()) != 0 || std::ferror(file.get())) throw std::runtime_error(path + ": write failed (disk full?)");
}

namespace {

constexpr const char* kPoseHeader =
    "frame\ttime_s\tbody\ttracked\tpredicted\tx\ty\tz\tqx\tqy\tqz\tqw\tmean_error_mm\tmarkers";

}  // namespace

std::vector<BodyPoseRecord> ParseBodyPoses(const std::string& text, const std::string& source) {
  std::vector<BodyPoseRecord> out;
  std::istringstream in(text);
  std::string line;
  size_t number = 0;
  auto fail = [&](const std::string& why) {
    throw std::runtime_error(source + ": line " + std::to_string(number) + ": " + why);
  };
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (number == 1) {
      if (line != kPoseHeader) fail("not a body pose file (expected the header: frame, time_s, body, ...)");
      continue;
    }
    if (line.empty()) continue;
    std::vector<std::string> cells;
    std::istringstream fields(line);
    for (std::string cell; std::getline(fields, cell, '\t');) cells.push_back(cell);
    if (cells.size() != 14) fail("expected 14 tab-separated columns, found " + std::to_string(cells.size()));
    auto number_at = [&](size_t i) {
      size_t used = 0;
      double v = 0.0;
      try {
        v = std::stod(cells[i], &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (cells[i].empty() || used != cells[i].size() || !std::isfinite(v))
        fail("column " + std::to_string(i + 1) + ": not a number");
      return v;
    };
    BodyPoseRecord r;
    const double frame = number_at(0);
    if (frame < 0.0 || frame > 1e15 || frame != std::floor(frame)) fail("frame must be a whole number >= 0");
    r.frame = static_cast<uint64_t>(frame);
    r.body = cells[2];
    if (r.body.empty() || r.body.size() > 255) fail("body name must be 1-255 bytes");
    const double tracked = number_at(3), predicted = number_at(4);
    if ((tracked != 0.0 && tracked != 1.0) || (predicted != 0.0 && predicted != 1.0)) fail("tracked/predicted must be 0 or 1");
    r.tracked = tracked == 1.0, r.predicted = predicted == 1.0;
    // A row without a pose has empty cells (older files: numbers, read and ignored as before).
    const bool empty = !r.tracked && !r.predicted &&
                       std::all_of(cells.begin() + 5, cells.begin() + 13, [](const std::string& c) { return c.empty(); });
    if (!empty) {
      r.pivot = Eigen::Vector3d(number_at(5), number_at(6), number_at(7));
      Eigen::Quaterniond q(number_at(11), number_at(8), number_at(9), number_at(10));
      if (r.tracked || r.predicted) {
        if (!(std::abs(q.norm() - 1.0) < 1e-3)) fail("orientation is not a unit quaternion");
        q.normalize();
      }
      r.orientation = q;
      r.mean_error_mm = number_at(12);
    }
    const double markers = number_at(13);
    if (markers < 0.0 || markers > 1e6 || markers != std::floor(markers)) fail("markers must be a whole number >= 0");
    r.markers = static_cast<size_t>(markers);
    out.push_back(std::move(r));
  }
  if (number == 0) throw std::runtime_error(source + ": empty");
  return out;
}

std::vector<BodyPoseRecord> ReadBodyPoses(const std::string& path) {
  return ParseBodyPoses(ReadRegularFile(path, kMaxRecordingFileBytes, "a body pose file"), path);
}

}  // namespace mocap
