// Frame-by-frame tracking of reconstructed points into labelled markers (seed 001 sections 4-5):
// every track's Kalman filter predicts the frame; points found through a track's own prediction
// go straight to it, the rest are assigned to predictions under a gate (greedy or optimal);
// markers without a point continue on the rigid-pair model's prediction, coast, then wait lost
// for re-acquisition so that an id survives an occlusion; new tracks are output only once
// confirmed, with their first frames back-filled.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "recon/prediction_matcher.h"
#include "recon/reconstructor.h"
#include "track/kalman.h"
#include "track/rigid_model.h"
#include "track/rigid_swaps.h"
#include "track/track_options.h"

namespace mocap {

enum class SampleKind : uint8_t { kMeasured, kPredicted, kFilled };

struct TrackSample {
  int marker = 0;  // output column, 0-based, stable for the track's life
  uint64_t frame_number = 0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_per_frame = Eigen::Vector3d::Zero();
  SampleKind kind = SampleKind::kMeasured;
};

// Who a point of the last Update belongs to, for live output that holds nothing back. Every
// track has an id from the frame it is born in (its first point is published then), kept while
// it is tentative, confirmed, lost and found again: provisional is a flag on that id, not
// another number. A confirmed track also has its marker (the output column of its samples,
// numbered in order of confirmation). A point without a track (seen by too few cameras to start
// one) has neither.
struct PointIdentity {
  uint64_t id = 0;   // the track's id (never reused), 0 when none
  int marker = -1;   // output column of a confirmed track, else -1
  bool confirmed() const { return marker >= 0; }
};

struct TrackerStats {
  long long births = 0;          // tracks confirmed
  long long reacquisitions = 0;  // lost tracks that found their marker again
  long long predicted_samples = 0;
  long long deaths = 0;
  long long cluster_repairs = 0;  // rigid clusters whose points were permuted back
};

class Tracker {
 public:
  // Checks the options (std::invalid_argument).
  explicit Tracker(const TrackerOptions& options);

  // Advances every track to frame_number and returns the predictions, most trusted first, for
  // Reconstructor::Process. Frame numbers must increase.
  const std::vector<PointPrediction>& Predict(uint64_t frame_number);
  // Assigns the frame's points and appends output samples (confirmed tracks only; a track
  // confirmed now also yields its earlier frames).
  void Update(uint64_t frame_number, const std::vector<ReconstructedPoint>& points,
              std::vector<TrackSample>* samples);

  // At the end of the data: tentative tracks that were measured in every frame of their short
  // life are confirmed and output (a marker that appears in the last frames is still a marker).
  void Finish(std::vector<TrackSample>* samples);

  // One entry per point of the last Update, in the points' order.
  const std::vector<PointIdentity>& point_identities() const { return point_identities_; }
  int NumMarkers() const { return next_marker_; }
  const TrackerStats& stats() const { return stats_; }
  // Follows the reconstruction's point error (one sigma, mm: Reconstructor::point_noise_mm):
  // the Kalman measurement noise and the smallest gate (kGateNoiseSigmas of it) widen to it,
  // never below their configured values. 0: unknown, nothing changes.
  static constexpr double kGateNoiseSigmas = 6.0;
  void FollowPointNoise(double point_noise_mm);

 private:
  enum class State { kFree, kTentative, kActive, kLost };
  struct Track {
    State state = State::kFree;
    int marker = -1;
    ConstantVelocityKalman filter;
    uint64_t filter_frame = 0;
    uint64_t last_measured = 0;
    int hits = 0;
    int age = 0;  // frames measured in total, orders predictions by trust
    uint64_t held = 0;  // drop-out frames since last measured (at most dropout_hold_s of them)
    int min_views = 0;  // fewest views of its tentative points: two views need a longer birth
    uint64_t serial = 0;  // the track's id, unique over the tracker's life (a slot is reused, a serial never)
    Eigen::Vector3d reference = Eigen::Vector3d::Zero();  // where a lost track is looked for
    Eigen::Vector3d last_point = Eigen::Vector3d::Zero();  // last measured position
    std::vector<std::pair<uint64_t, Eigen::Vector3d>> history;  // tentative frames
  };

  // What one Update has found so far, per track slot (and per point for point_taken).
  // Kept between frames (Reset refills it) so that a frame allocates nothing once warmed up.
  struct FrameMatch {
    void Reset(size_t num_slots, size_t num_points);
    std::vector<int> point_of_slot;  // point index or -1
    std::vector<char> point_taken;
    std::vector<char> moved;  // re-assigned around a miss
    std::vector<char> measured;  // active and holding a point before the rigid model runs
    std::vector<Eigen::Vector3d> position_of_slot;
    std::vector<char> has_rigid;
    std::vector<Eigen::Vector3d> rigid_position;
    std::vector<char> found_wide;  // the point lies outside the track's own gate
  };
  // Update's numbered steps, in order.
  void TakeHintedPoints(const std::vector<ReconstructedPoint>& points, FrameMatch* match) const;
  void MatchPredictions(const std::vector<ReconstructedPoint>& points, FrameMatch* match);
  void PredictFromRigidModel(const std::vector<ReconstructedPoint>& points, FrameMatch* match);
  void SearchWide(const std::vector<ReconstructedPoint>& points, FrameMatch* match);
  void RepairRigidClusters(const std::vector<ReconstructedPoint>& points, FrameMatch* match);
  void ApplyMeasurements(uint64_t frame_number, const std::vector<ReconstructedPoint>& points,
                         const FrameMatch& match, std::vector<TrackSample>* samples);
  void HandleUnmeasured(uint64_t frame_number, const FrameMatch& match, std::vector<TrackSample>* samples);
  void BirthTracks(uint64_t frame_number, const std::vector<ReconstructedPoint>& points, const FrameMatch& match,
                   std::vector<TrackSample>* samples);
  void IdentifyPoints(const FrameMatch& match, size_t num_points);
  void Identify(const Track& track, PointIdentity* identity) const;

  int NewTrack(uint64_t frame_number, const Eigen::Vector3d& position);
  void FreeTrack(int slot);
  // Tentative -> active: a marker number, a birth, and the samples of its tentative frames.
  void Promote(Track* track, std::vector<TrackSample>* samples);
  double GateOf(const Track& track) const;
  // Frames a tentative track must be measured in a row before it is confirmed.
  int BirthFramesOf(const Track& track) const;
  TrackSample SampleOf(const Track& track, uint64_t frame_number, SampleKind kind) const;
  // Mean innovation (measured - predicted) of the `neighbours` measured tracks predicted
  // nearest to slot's prediction, within radius_mm (neighbours <= kMaxNeighbours).
  static constexpr int kMaxNeighbours = 4;
  Eigen::Vector3d NeighbourInnovation(int slot, const std::vector<char>& measured,
                                      const std::vector<Eigen::Vector3d>& position_of_slot, int neighbours,
                                      double radius_mm) const;
  void ReassignAroundMisses(const std::vector<ReconstructedPoint>& points, std::vector<int>* point_of_slot,
                            std::vector<char>* point_taken, std::vector<char>* moved);
  // Tracks to search for points: each slot's search centre and gate (mm).
  struct SearchList {
    std::vector<int> slots;
    std::vector<Eigen::Vector3d> centres;
    std::vector<double> gates;
    void Clear() {
      slots.clear();
      centres.clear();
      gates.clear();
    }
    void Add(int slot, const Eigen::Vector3d& centre, double gate) {
      slots.push_back(slot);
      centres.push_back(centre);
      gates.push_back(gate);
    }
  };
  void AssignByDistance(const SearchList& search, const std::vector<ReconstructedPoint>& points,
                        std::vector<int>* point_of_slot, std::vector<char>* point_taken);

  TrackerOptions configured_;
  TrackerOptions options_;  // configured_ with the gates widened to the point noise
  bool following_noise_ = false;  // options_ differ from configured_
  std::vector<Track> tracks_;
  std::vector<int> free_slots_;
  RigidModel rigid_;
  RigidSwapResolver swaps_;
  std::vector<int> held_before_;  // RepairRigidClusters' scratch
  std::vector<char> swap_eligible_, swap_changed_;  // per slot, reused every frame
  FrameMatch match_;  // Update's, reused every frame
  std::vector<int> rigid_slots_;  // ApplyMeasurements' scratch: the rigid model's input
  std::vector<Eigen::Vector3d> rigid_positions_;
  // Scratch of one step at a time, kept so that a frame allocates none of them: Predict's order
  // (-age, slot); the search MatchPredictions and SearchWide hand to AssignByDistance, and its
  // free points; SearchWide's assignment before its own.
  std::vector<std::pair<int, int>> order_;
  SearchList search_;
  std::vector<int> free_points_;
  std::vector<int> wide_before_;
  int next_marker_ = 0;
  uint64_t next_serial_ = 1;
  std::vector<PointIdentity> point_identities_;
  std::vector<std::pair<int, int>> born_;  // (point, slot) of this frame's new tracks
  uint64_t predicted_frame_ = 0;
  bool predicted_ = false;
  bool updated_ = false;  // last_update_frame_ is set
  uint64_t last_update_frame_ = 0;
  std::vector<PointPrediction> predictions_;
  TrackerStats stats_;
};

}  // namespace mocap
