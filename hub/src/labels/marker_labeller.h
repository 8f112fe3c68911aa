// Names for anonymous 3D points, frame by frame, from a marker set (labels/marker_set.h), for
// live use (serve) and as the first pass of offline labelling (trial_labeller.h).
//
// Labels belong to tracks (the tracker's marker numbers): once a track holds a name it keeps it
// while its distances agree, so a name follows its marker through the frames without being
// guessed again. Per frame:
//  1. Every point of a labelled track takes the track's name.
//  2. Swap guard: each labelled point's distances to the other labelled markers of its segment
//     are compared with this subject's own distances (learned while labelled, once seen
//     `learn_frames` times) and, where a segment partner lets it, with where the partners place
//     it; a point that breaks most of its checks loses its name, and so does its track: a name is
//     never carried across a swap.
//  3. The marker set's mean shape is placed on the labelled points (an upright similarity fit,
//     shape_fit.h), or searched for from several headings (and, without a known up axis, every
//     axis) when fewer than four points are labelled.
//  4. Every unlabelled point is proposed the name of the missing marker placed nearest it (one
//     to one, optimal): placed by its segment partners when some of them are labelled (they carry
//     it rigidly from the last frame all were seen: this subject's own geometry), else by the
//     mean shape. A proposal that breaks a labelled partner's distance is dropped. A proposal from
//     the partners names the track at once; one from the mean shape is a vote, and a track takes
//     the name once it has `min_votes` votes and at least `min_vote_share` of its votes.
//     Points without a track take names from their partners only, for that frame.
// Every point's proposal (made for all points each frame) is also kept as a vote per track,
// which offline labelling sums over whole track segments. Pure: no clock, no I/O.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

#include "labels/marker_set.h"
#include "labels/shape_fit.h"

namespace mocap {

struct LabellerOptions {
  int up_axis = -1;                    // the data's vertical axis (0-2, positive up); -1: searched
  double shape_gate_mm = 150.0;        // farther from the placed mean shape: not proposed
  double local_gate_mm = 30.0;         // farther from where segment partners place it: not proposed
  double distance_tolerance_mm = 8.0;  // a segment distance this far (and 5 sd) off its learned value breaks
  double template_tolerance = 0.35;    // before then: outside the set's [min, max] widened by this share
  int min_votes = 5;
  double min_vote_share = 0.6;
  int learn_frames = 20;
  int search_headings = 12;
  void Check() const;  // throws std::invalid_argument
};

struct LabellerStats {
  long long named_points = 0;     // points given a name, over all frames
  long long commits = 0;          // tracks given a name
  long long revocations = 0;      // names taken back by the swap guard
  long long searches = 0;         // frames where the mean shape was searched for from scratch
};

class MarkerLabeller {
 public:
  // Throws std::invalid_argument for bad options or a set without a mean shape.
  MarkerLabeller(MarkerSet set, const LabellerOptions& options = {});

  // One frame: the points (mm, world) and their tracks (>= 0; -1: none). Returns per point the
  // marker-set index of its name, or -1. Frames must come in order.
  const std::vector<int>& Update(const std::vector<Eigen::Vector3d>& points, const std::vector<int64_t>& tracks);

  // Of the last Update, per point: the name the mean shape proposed (a vote), or -1.
  const std::vector<int>& proposals() const { return proposals_; }
  // Tracks that lost their name in the last Update.
  const std::vector<int64_t>& revoked() const { return revoked_; }
  const MarkerSet& set() const { return set_; }
  const LabellerStats& stats() const { return stats_; }

 private:
  struct TrackState {
    int label = -1;
    std::unordered_map<int, int> votes;
    int total_votes = 0;
    long long labelled_since = 0;  // frame counter when it took its name
  };
  struct PairLearned {
    double sum = 0.0, sum_squares = 0.0;
    int n = 0;
  };

  void SwapGuard(const std::vector<Eigen::Vector3d>& points, const std::vector<int64_t>& tracks);
  bool Consistent(int label, const Eigen::Vector3d& at, const std::vector<Eigen::Vector3d>& points, int self) const;
  bool DistanceBreaks(int a, int b, double distance) const;
  bool AlignShape(const std::vector<Eigen::Vector3d>& canonical);
  double Icp(const std::vector<Eigen::Vector3d>& canonical, UprightTransform* fit, int iterations) const;
  bool PlaceByPartners(int label, const std::vector<Eigen::Vector3d>& points, Eigen::Vector3d* at) const;
  void Learn(const std::vector<Eigen::Vector3d>& points);
  void Propose(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& canonical,
               const std::vector<int64_t>& tracks);
  void Commit(int64_t track, int label);

  MarkerSet set_;
  LabellerOptions options_;
  std::vector<int> shape_markers_;  // markers with a mean-shape place
  Eigen::Matrix3d to_canonical_ = Eigen::Matrix3d::Identity();  // data -> z up
  bool up_known_ = false;
  UprightTransform shape_fit_;
  bool shape_valid_ = false;
  std::unordered_map<int64_t, TrackState> tracks_;
  std::vector<int64_t> owner_;          // per label: the track holding it, -1
  std::vector<int> point_of_label_;     // this frame
  std::vector<PairLearned> learned_;    // per pair a * n + b, segment pairs only
  // Per label: its position and its segment partners' positions the last frame all were labelled.
  std::vector<std::vector<Eigen::Vector3d>> snapshot_;
  std::vector<char> has_snapshot_;
  std::vector<int> labels_, proposals_;
  std::vector<int64_t> revoked_;
  long long frame_counter_ = 0;
  LabellerStats stats_;
};

}  // namespace mocap
