// Rigid bodies over a whole recording (see body_trajectories.h).
#include "bodies/body_trajectories.h"

#include <cstdio>
#include <memory>
#include <stdexcept>

namespace mocap {

std::vector<BodyPoseRow> TrackBodies(const MarkerTrajectories& markers, const std::vector<RigidBodyDefinition>& bodies,
                                     const BodyTrackerOptions& options) {
  BodyTracker tracker(bodies, options);
  std::vector<BodyPoseRow> rows(markers.NumFrames());
  std::vector<Eigen::Vector3d> points;
  for (size_t f = 0; f < markers.NumFrames(); ++f) {
    points.clear();
    for (size_t m = 0; m < markers.NumMarkers(); ++m)
      if (markers.Has(f, m)) points.push_back(markers.At(f, m));
    rows[f].frame_number = markers.frame_numbers[f];
    rows[f].poses = tracker.Update(points);
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
      std::fprintf(file.get(), "%llu\t%.6f\t%s\t%d\t%d\t%.3f\t%.3f\t%.3f\t%.6f\t%.6f\t%.6f\t%.6f\t%.3f\t%zu\n",
                   static_cast<unsigned long long>(row.frame_number + 1), static_cast<double>(row.frame_number) / rate_hz,
                   bodies[b].name.c_str(), p.tracked ? 1 : 0, p.predicted ? 1 : 0, p.pivot.x(), p.pivot.y(), p.pivot.z(),
                   q.x(), q.y(), q.z(), q.w(), p.mean_error_mm, p.markers);
    }
  if (std::fflush(file.get()) != 0 || std::ferror(file.get())) throw std::runtime_error(path + ": write failed (disk full?)");
}

}  // namespace mocap
