// Contested predictions grouped, assigned to blobs per camera, triangulated and judged.
#include "recon/contested_groups.h"

#include <algorithm>
#include <limits>
#include <numeric>

#include <Eigen/Core>

#include "util/assignment.h"

namespace mocap {
namespace {

// Union-find root with path halving.
int Root(std::vector<int>* parent, int i) {
  while ((*parent)[i] != i) {
    (*parent)[i] = (*parent)[(*parent)[i]];
    i = (*parent)[i];
  }
  return i;
}

// A point the matcher would need three views for (it has no track hint): two views are left to
// the matcher, which accepts them only where few other cameras should see the point.
constexpr size_t kMinGroupPointViews = 3;

// A prediction and a blob within its gate, in one camera.
struct Candidate {
  int member;  // index within the group
  int observation;
  double cost;  // squared distance over the squared gate radius: at most 1
  int component = 0;
};

}  // namespace

void FindContestedGroups(const std::vector<PointPrediction>& predictions, const std::vector<char>& contested,
                         double factor, double gate_cap_mm, std::vector<int>* group_begin, std::vector<int>* members) {
  group_begin->assign(1, 0);
  members->clear();
  std::vector<int> by_x;
  for (size_t i = 0; i < predictions.size() && i < contested.size(); ++i) {
    if (contested[i]) by_x.push_back(static_cast<int>(i));
  }
  if (by_x.empty()) return;
  const auto x_of = [&](int i) { return predictions[static_cast<size_t>(i)].point_in_world.x(); };
  std::sort(by_x.begin(), by_x.end(), [&](int a, int b) { return x_of(a) < x_of(b) || (x_of(a) == x_of(b) && a < b); });
  const auto gate_of = [&](int i) { return std::min(predictions[static_cast<size_t>(i)].gate_mm, gate_cap_mm); };
  double max_gate = 0.0;
  for (int i : by_x) max_gate = std::max(max_gate, gate_of(i));
  std::vector<int> parent(predictions.size());
  std::iota(parent.begin(), parent.end(), 0);
  // The same sweep as MarkContested: a pair is only near while its x distance is.
  for (size_t a = 0; a < by_x.size(); ++a) {
    const Eigen::Vector3d& first = predictions[static_cast<size_t>(by_x[a])].point_in_world;
    const double reach = factor * (gate_of(by_x[a]) + max_gate);
    for (size_t b = a + 1; b < by_x.size(); ++b) {
      const Eigen::Vector3d& second = predictions[static_cast<size_t>(by_x[b])].point_in_world;
      if (second.x() - first.x() > reach) break;
      const double limit = factor * (gate_of(by_x[a]) + gate_of(by_x[b]));
      if ((second - first).squaredNorm() < limit * limit) parent[Root(&parent, by_x[a])] = Root(&parent, by_x[b]);
    }
  }
  // Members in index order, groups in the order of their first (oldest) member.
  std::sort(by_x.begin(), by_x.end());
  std::vector<int> slot(predictions.size(), -1);
  std::vector<std::vector<int>> groups;
  for (int i : by_x) {
    int& s = slot[static_cast<size_t>(Root(&parent, i))];
    if (s < 0) {
      s = static_cast<int>(groups.size());
      groups.emplace_back();
    }
    groups[static_cast<size_t>(s)].push_back(i);
  }
  for (const std::vector<int>& group : groups) {
    members->insert(members->end(), group.begin(), group.end());
    group_begin->push_back(static_cast<int>(members->size()));
  }
}

void ContestedGroupResolver::AssignInCamera(const RigModel& rig, const FrameViews& views, const BlobIndex& index,
                                            const std::vector<PointPrediction>& predictions, const int* members,
                                            int count, int camera, const UseCounts& used) {
  const CameraModel& cam = rig.camera(camera);
  const int num_cameras = rig.NumCameras();
  thread_local std::vector<Candidate> candidates;
  thread_local std::vector<int> parent, rows;
  std::vector<int>& columns = candidates_;
  // Every (member, blob) pair within the member's gate, its cost the squared distance over the
  // squared gate radius.
  candidates.clear();
  for (int k = 0; k < count; ++k) {
    const PointPrediction& prediction = predictions[static_cast<size_t>(members[k])];
    const Eigen::Vector3d p = cam.cam_from_world_rotation * prediction.point_in_world + cam.cam_from_world_translation;
    if (!(p.z() > triangulation_.min_depth_mm)) continue;
    const double gate_px =
        std::clamp(cam.focal_px * prediction.gate_mm / p.z(), options_.min_gate_px, options_.max_gate_px);
    const double radius = gate_px / cam.focal_px;
    index.ForEachWithin(views, camera, p.head<2>() / p.z(), radius, [&](int o, double distance) {
      if (IsAvailable(views.observations[static_cast<size_t>(o)], used[static_cast<size_t>(o)]))
        candidates.push_back({k, o, distance * distance / (radius * radius)});
    });
  }
  if (candidates.empty()) return;
  // The members that reach a common blob, transitively, compete: one small assignment each. A
  // camera that sees the group spread out makes many components of one member, which take their
  // nearest blob.
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
    return a.observation < b.observation || (a.observation == b.observation && a.member < b.member);
  });
  parent.resize(static_cast<size_t>(count));
  std::iota(parent.begin(), parent.end(), 0);
  for (size_t i = 1; i < candidates.size(); ++i) {
    if (candidates[i].observation == candidates[i - 1].observation)
      parent[static_cast<size_t>(Root(&parent, candidates[i].member))] = Root(&parent, candidates[i - 1].member);
  }
  // Stable by component: within one, blobs stay in ascending order (ties do not depend on the grid).
  for (Candidate& candidate : candidates) candidate.component = Root(&parent, candidate.member);
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& a, const Candidate& b) { return a.component < b.component; });
  for (size_t begin = 0; begin < candidates.size();) {
    size_t end = begin + 1;
    while (end < candidates.size() && candidates[end].component == candidates[begin].component) ++end;
    rows.clear();
    columns.clear();
    for (size_t i = begin; i < end; ++i) {
      if (std::find(rows.begin(), rows.end(), candidates[i].member) == rows.end())
        rows.push_back(candidates[i].member);
      if (columns.empty() || columns.back() != candidates[i].observation) columns.push_back(candidates[i].observation);
    }
    if (rows.size() == 1) {
      // One member alone: its nearest blob (ties to the lower observation, the first in order).
      const Candidate* best = &candidates[begin];
      for (size_t i = begin + 1; i < end; ++i) {
        if (candidates[i].cost < best->cost) best = &candidates[i];
      }
      assigned_[static_cast<size_t>(best->member * num_cameras + camera)] = best->observation;
    } else {
      std::sort(rows.begin(), rows.end());
      Eigen::MatrixXd cost = Eigen::MatrixXd::Constant(static_cast<Eigen::Index>(rows.size()),
                                                       static_cast<Eigen::Index>(columns.size()),
                                                       std::numeric_limits<double>::infinity());
      for (size_t i = begin; i < end; ++i) {
        const auto row = std::lower_bound(rows.begin(), rows.end(), candidates[i].member) - rows.begin();
        const auto column =
            std::lower_bound(columns.begin(), columns.end(), candidates[i].observation) - columns.begin();
        cost(row, column) = candidates[i].cost;
      }
      const std::vector<int> chosen = SolveAssignment(cost, 1.0);
      for (size_t r = 0; r < rows.size(); ++r) {
        const int j = chosen[r];
        if (j >= 0) assigned_[static_cast<size_t>(rows[r] * num_cameras + camera)] = columns[static_cast<size_t>(j)];
      }
    }
    begin = end;
  }
}

int ContestedGroupResolver::Resolve(const RigModel& rig, const FrameViews& views, const BlobIndex& index,
                                    const std::vector<PointPrediction>& predictions,
                                    const std::vector<char>& contested, UseCounts* used,
                                    std::vector<TriangulatedPoint>* points, const std::vector<char>* shared) {
  FindContestedGroups(predictions, contested, options_.contested_gate_factor, options_.contested_gate_cap_mm,
                      &group_begin_, &members_);
  const int num_cameras = rig.NumCameras();
  int made = 0;
  for (size_t g = 0; g + 1 < group_begin_.size(); ++g) {
    ++groups_;
    const int* members = members_.data() + group_begin_[g];
    const int count = group_begin_[g + 1] - group_begin_[g];
    assigned_.assign(static_cast<size_t>(count * num_cameras), -1);
    for (int c = 0; c < num_cameras; ++c) AssignInCamera(rig, views, index, predictions, members, count, c, *used);
    // Members one after the other: a blob an earlier member's point took (its completion may
    // take a blob assigned to a later member that its own views disagree with) is not reused.
    // A member's point stands only when every blob it was assigned agrees (no view dropped):
    // otherwise its blobs go to the matcher, whose epipolar consistency decides.
    for (int k = 0; k < count; ++k) {
      picked_.clear();
      for (int c = 0; c < num_cameras; ++c) {
        const int o = assigned_[static_cast<size_t>(k * num_cameras + c)];
        if (o >= 0 && IsAvailable(views.observations[static_cast<size_t>(o)], (*used)[static_cast<size_t>(o)]))
          picked_.push_back(o);
      }
      const size_t gathered = picked_.size();
      if (gathered < kMinGroupPointViews || !TriangulateRobust(rig, views, picked_, triangulation_, &point_, shared) ||
          point_.observations.size() != gathered)
        continue;
      CompleteViews(rig, views, index, *used, triangulation_, &point_, shared);
      if (!JudgePredictedPoint(options_, predictions[static_cast<size_t>(members[k])], gathered, point_)) continue;
      MarkUsed(point_, used);
      points->push_back(point_);
      ++made;
    }
  }
  return made;
}

}  // namespace mocap
