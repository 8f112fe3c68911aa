// Track life cycle: tentative -> active <-> lost -> free.
#include "track/tracker.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "track/assignment.h"
#include "util/assignment.h"

namespace mocap {

Tracker::Tracker(const TrackerOptions& options)
    : configured_((options.Check(), options)), options_(options), rigid_(options.rigid), swaps_(options.swaps) {}

void Tracker::FollowPointNoise(double point_noise_mm) {
  // The configured values were tuned on 0.05-0.3 px rigs, whose points come out at 0.2-0.7 mm:
  // within a factor of two of them they stand (the figures of those rigs stay as they were).
  if (!(point_noise_mm > 2.0 * configured_.kalman.measurement_noise_mm)) {
    if (following_noise_) options_ = configured_;  // once, not every frame of a precise rig
    following_noise_ = false;
    return;
  }
  following_noise_ = true;
  options_.kalman.measurement_noise_mm = std::max(configured_.kalman.measurement_noise_mm, point_noise_mm);
  options_.min_gate_mm = std::max(configured_.min_gate_mm, kGateNoiseSigmas * point_noise_mm);
  options_.max_gate_mm = std::max(configured_.max_gate_mm, options_.min_gate_mm);
}

int Tracker::BirthFramesOf(const Track& track) const {
  return track.min_views >= 3 ? options_.birth_frames : std::max(options_.birth_frames, options_.two_view_birth_frames);
}

int Tracker::NewTrack(uint64_t frame_number, const Eigen::Vector3d& position) {
  int slot;
  if (!free_slots_.empty()) {
    slot = free_slots_.back();
    free_slots_.pop_back();
  } else {
    slot = static_cast<int>(tracks_.size());
    tracks_.emplace_back();
  }
  Track& track = tracks_[slot];
  track = Track();
  track.state = State::kTentative;
  track.serial = next_serial_++;
  track.filter = ConstantVelocityKalman(position, options_.kalman);
  track.filter_frame = frame_number;
  track.last_measured = frame_number;
  track.reference = position;
  track.last_point = position;
  return slot;
}

void Tracker::FreeTrack(int slot) {
  if (tracks_[slot].state == State::kActive || tracks_[slot].state == State::kLost) ++stats_.deaths;
  tracks_[slot] = Track();
  rigid_.ResetSlot(slot);
  free_slots_.push_back(slot);
}

double Tracker::GateOf(const Track& track) const {
  const double gate =
      std::clamp(options_.gate_sigmas * track.filter.InnovationStd(options_.kalman.measurement_noise_mm),
                 options_.min_gate_mm, options_.max_gate_mm);
  // A track two or three frames old has a velocity from one difference: any glitch in it (a
  // marker's first frames often jump) would kill the track, so young tracks search wider.
  return track.state == State::kTentative ? std::max(gate, 3.0 * options_.min_gate_mm) : gate;
}

void Tracker::Finish(std::vector<TrackSample>* samples) {
  for (Track& track : tracks_) {
    if (track.state != State::kTentative) continue;
    // Measured in every frame since its birth with enough views; only the data ended too soon.
    // Begun on two views, it must still have shown that it moves like a marker.
    if (track.min_views < 3 && track.hits < BirthFramesOf(track)) continue;
    Promote(&track, samples);
  }
}

void Tracker::Promote(Track* track, std::vector<TrackSample>* samples) {
  track->state = State::kActive;
  track->marker = next_marker_++;
  ++stats_.births;
  // The frames it was tentative in are written now, under its new marker.
  for (const auto& [frame, position] : track->history) {
    TrackSample sample = SampleOf(*track, frame, SampleKind::kMeasured);
    sample.position = position;
    samples->push_back(sample);
  }
  track->history.clear();
  track->history.shrink_to_fit();
}

TrackSample Tracker::SampleOf(const Track& track, uint64_t frame_number, SampleKind kind) const {
  TrackSample sample;
  sample.marker = track.marker;
  sample.frame_number = frame_number;
  sample.position = track.filter.position();
  sample.velocity_per_frame = track.filter.velocity() / options_.rate_hz;
  sample.kind = kind;
  return sample;
}

const std::vector<PointPrediction>& Tracker::Predict(uint64_t frame_number) {
  const uint64_t coast = static_cast<uint64_t>(std::lround(options_.coast_s * options_.rate_hz));
  predictions_.clear();
  std::vector<std::pair<int, int>>& order = order_;  // (-age, slot)
  order.clear();
  for (int slot = 0; slot < static_cast<int>(tracks_.size()); ++slot) {
    Track& track = tracks_[slot];
    if (track.state == State::kFree) continue;
    if (frame_number > track.filter_frame) {
      track.filter.Predict(static_cast<double>(frame_number - track.filter_frame) / options_.rate_hz);
      track.filter_frame = frame_number;
    }
    // Confirmed tracks, and tentative ones measured twice: a track seen once has no velocity,
    // and its wide search would gather other markers' blobs; its next point comes from the
    // matcher. A track held through a drop-out longer than a coast is left out too (without the
    // hold it would be lost, and out): a prediction that old would make the reconstruction pair
    // other markers' blobs near it into a ghost; the tracker's own search finds its point among
    // the points reconstructed without it.
    const bool stale = track.held > 0 && frame_number - track.last_measured > coast;
    if ((track.state == State::kActive && !stale) || (track.state == State::kTentative && track.hits >= 2)) {
      order.emplace_back(-track.age, slot);
    }
  }
  std::sort(order.begin(), order.end());
  for (const auto& [negative_age, slot] : order) {
    PointPrediction prediction;
    prediction.track_id = slot;
    prediction.point_in_world = tracks_[slot].filter.position();
    prediction.gate_mm = GateOf(tracks_[slot]);
    predictions_.push_back(prediction);
  }
  predicted_frame_ = frame_number;
  predicted_ = true;
  return predictions_;
}

Eigen::Vector3d Tracker::NeighbourInnovation(int slot, const std::vector<char>& measured,
                                             const std::vector<Eigen::Vector3d>& position_of_slot, int neighbours,
                                             double radius_mm) const {
  // The markers of one limb lag their predictions together when it accelerates hard: the
  // nearest measured markers' innovations (measured - predicted) say by how much.
  const Eigen::Vector3d& centre = tracks_[slot].filter.position();
  std::pair<double, int> nearest[kMaxNeighbours];
  neighbours = std::min(neighbours, kMaxNeighbours);
  int count = 0;
  for (int other = 0; other < static_cast<int>(measured.size()); ++other) {
    if (!measured[other]) continue;
    const double d = (tracks_[other].filter.position() - centre).norm();
    if (d > radius_mm) continue;
    if (count < neighbours) {
      nearest[count++] = {d, other};
    } else {
      auto* farthest = std::max_element(nearest, nearest + neighbours);
      if (d < farthest->first) *farthest = {d, other};
    }
  }
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int k = 0; k < count; ++k) {
    sum += position_of_slot[nearest[k].second] - tracks_[nearest[k].second].filter.position();
  }
  return count > 0 ? Eigen::Vector3d(sum / count) : Eigen::Vector3d::Zero();
}

void Tracker::AssignByDistance(const SearchList& search, const std::vector<ReconstructedPoint>& points,
                               std::vector<int>* point_of_slot, std::vector<char>* point_taken) {
  const std::vector<int>& slots = search.slots;
  std::vector<int>& free_points = free_points_;
  free_points.clear();
  for (int p = 0; p < static_cast<int>(points.size()); ++p) {
    if (!(*point_taken)[p]) free_points.push_back(p);
  }
  if (slots.empty() || free_points.empty()) return;
  Eigen::MatrixXd cost(slots.size(), free_points.size());
  for (size_t r = 0; r < slots.size(); ++r) {
    for (size_t c = 0; c < free_points.size(); ++c) {
      cost(r, c) = (points[free_points[c]].point_in_world - search.centres[r]).norm();
    }
  }
  const std::vector<int> column_of_row = Assign(options_.assignment, cost, search.gates);
  for (size_t r = 0; r < slots.size(); ++r) {
    if (column_of_row[r] < 0) continue;
    const int p = free_points[column_of_row[r]];
    (*point_of_slot)[slots[r]] = p;
    (*point_taken)[p] = 1;
  }
}

void Tracker::ReassignAroundMisses(const std::vector<ReconstructedPoint>& points,
                                   std::vector<int>* point_of_slot, std::vector<char>* point_taken,
                                   std::vector<char>* moved) {
  const int num_slots = static_cast<int>(tracks_.size());
  // Confirmed tracks whose constant-velocity prediction failed: no point within the gate, or a
  // point (from the prediction pass, which allows more) beyond it.
  std::vector<int> misses;
  for (int slot = 0; slot < num_slots; ++slot) {
    const Track& track = tracks_[slot];
    if (track.state != State::kActive) continue;
    const int p = (*point_of_slot)[slot];
    if (p < 0 || (points[p].point_in_world - track.filter.position()).norm() > GateOf(track)) {
      misses.push_back(slot);
    }
  }
  if (misses.empty()) return;
  const double radius = options_.wide_gate_mm;
  const double radius2 = radius * radius;
  auto near_a_miss = [&](const Eigen::Vector3d& x) {
    for (int miss : misses) {
      if ((x - tracks_[miss].filter.position()).squaredNorm() <= radius2) return true;
    }
    return false;
  };
  // The neighbourhood: confirmed tracks predicted near a miss, with the points they hold and
  // the free points near a miss.
  std::vector<int> slots;
  std::vector<int> cluster_points;
  for (int slot = 0; slot < num_slots; ++slot) {
    if (tracks_[slot].state != State::kActive || !near_a_miss(tracks_[slot].filter.position())) continue;
    slots.push_back(slot);
    if ((*point_of_slot)[slot] >= 0) cluster_points.push_back((*point_of_slot)[slot]);
  }
  for (int p = 0; p < static_cast<int>(points.size()); ++p) {
    if (!(*point_taken)[p] && near_a_miss(points[p].point_in_world)) cluster_points.push_back(p);
  }
  if (slots.size() < 2 || cluster_points.empty()) return;

  // A limb that accelerates hard drags all its markers off their predictions alike: what tells
  // them apart is where they sit relative to each other. Each track's centre is its prediction
  // shifted by the mean innovation of the nearest tracks holding a point (itself included), and
  // the neighbourhood is assigned again against these centres. Two markers that traded points
  // leave that mean unchanged, so the shift does not depend on the assignment being right.
  const int n = static_cast<int>(slots.size());
  std::vector<int> point_of_row(n);
  for (int r = 0; r < n; ++r) point_of_row[r] = (*point_of_slot)[slots[r]];
  // Only the neighbourhood's tracks, with the points this round gave them, count as measured.
  std::vector<char> measured(num_slots, 0);
  std::vector<Eigen::Vector3d> position_of_slot(num_slots);
  Eigen::MatrixXd cost(n, cluster_points.size());
  for (int pass = 0; pass < 2; ++pass) {
    for (int r = 0; r < n; ++r) {
      measured[slots[r]] = point_of_row[r] >= 0;
      if (measured[slots[r]]) position_of_slot[slots[r]] = points[point_of_row[r]].point_in_world;
    }
    for (int r = 0; r < n; ++r) {
      const Eigen::Vector3d centre =
          tracks_[slots[r]].filter.position() +
          NeighbourInnovation(slots[r], measured, position_of_slot, kMaxNeighbours,
                              std::numeric_limits<double>::infinity());
      for (size_t c = 0; c < cluster_points.size(); ++c) {
        cost(r, c) = (points[cluster_points[c]].point_in_world - centre).norm();
      }
    }
    const std::vector<int> column_of_row = SolveAssignment(cost, radius);
    for (int r = 0; r < n; ++r) {
      point_of_row[r] = column_of_row[r] < 0 ? -1 : cluster_points[column_of_row[r]];
    }
  }
  for (int r = 0; r < n; ++r) {
    const int before = (*point_of_slot)[slots[r]];
    if (before >= 0) (*point_taken)[before] = 0;
  }
  for (int r = 0; r < n; ++r) {
    const int slot = slots[r];
    if (point_of_row[r] != (*point_of_slot)[slot]) (*moved)[slot] = 1;
    (*point_of_slot)[slot] = point_of_row[r];
    if (point_of_row[r] >= 0) (*point_taken)[point_of_row[r]] = 1;
  }
}

void Tracker::Update(uint64_t frame_number, const std::vector<ReconstructedPoint>& points,
                     std::vector<TrackSample>* samples) {
  if (!predicted_ || predicted_frame_ != frame_number) Predict(frame_number);
  predicted_ = false;
  match_.Reset(tracks_.size(), points.size());
  FrameMatch& match = match_;
  TakeHintedPoints(points, &match);
  MatchPredictions(points, &match);
  PredictFromRigidModel(points, &match);
  SearchWide(points, &match);
  RepairRigidClusters(points, &match);
  ApplyMeasurements(frame_number, points, match, samples);
  HandleUnmeasured(frame_number, match, samples);
  // Tracks created last so that this frame's steps did not see them.
  BirthTracks(frame_number, points, match, samples);
  IdentifyPoints(match, points.size());
}

// After every step: each point's track as it stands at the end of the frame.
void Tracker::IdentifyPoints(const FrameMatch& match, size_t num_points) {
  point_identities_.assign(num_points, PointIdentity());
  for (size_t slot = 0; slot < match.point_of_slot.size(); ++slot) {
    const int p = match.point_of_slot[slot];
    if (p >= 0) Identify(tracks_[slot], &point_identities_[p]);
  }
  for (const auto& [p, slot] : born_) Identify(tracks_[slot], &point_identities_[p]);
}

void Tracker::Identify(const Track& track, PointIdentity* identity) const {
  identity->id = track.serial;
  identity->marker = track.marker;  // -1 until confirmed
}

void Tracker::FrameMatch::Reset(size_t num_slots, size_t num_points) {
  point_of_slot.assign(num_slots, -1);
  point_taken.assign(num_points, 0);
  moved.assign(num_slots, 0);
  measured.assign(num_slots, 0);
  position_of_slot.assign(num_slots, Eigen::Vector3d::Zero());
  has_rigid.assign(num_slots, 0);
  rigid_position.resize(num_slots);  // read only where has_rigid is set
  found_wide.assign(num_slots, 0);
}

// 1. Points found through a track's own prediction.
void Tracker::TakeHintedPoints(const std::vector<ReconstructedPoint>& points, FrameMatch* match) const {
  const int num_slots = static_cast<int>(tracks_.size());
  for (int p = 0; p < static_cast<int>(points.size()); ++p) {
    const int slot = points[p].track_hint;
    if (slot < 0 || slot >= num_slots || match->point_of_slot[slot] >= 0) continue;
    if (tracks_[slot].state != State::kActive && tracks_[slot].state != State::kTentative) continue;
    match->point_of_slot[slot] = p;
    match->point_taken[p] = 1;
  }
}

// 2. The other points against the remaining predictions.
void Tracker::MatchPredictions(const std::vector<ReconstructedPoint>& points, FrameMatch* match) {
  search_.Clear();
  for (int slot = 0; slot < static_cast<int>(tracks_.size()); ++slot) {
    const Track& track = tracks_[slot];
    if ((track.state == State::kActive || track.state == State::kTentative) &&
        match->point_of_slot[slot] < 0) {
      search_.Add(slot, track.filter.position(), GateOf(track));
    }
  }
  AssignByDistance(search_, points, &match->point_of_slot, &match->point_taken);
  ReassignAroundMisses(points, &match->point_of_slot, &match->point_taken, &match->moved);
}

// 3. Rigid-model predictions for confirmed tracks still without a point, from the markers
// measured so far this frame.
void Tracker::PredictFromRigidModel(const std::vector<ReconstructedPoint>& points, FrameMatch* match) {
  const int num_slots = static_cast<int>(tracks_.size());
  for (int slot = 0; slot < num_slots; ++slot) {
    if (match->point_of_slot[slot] >= 0 && tracks_[slot].state == State::kActive) {
      match->measured[slot] = 1;
      match->position_of_slot[slot] = points[match->point_of_slot[slot]].point_in_world;
    }
  }
  for (int slot = 0; slot < num_slots; ++slot) {
    Track& track = tracks_[slot];
    if (match->point_of_slot[slot] >= 0) continue;
    if (track.state != State::kActive && track.state != State::kLost) continue;
    const Eigen::Vector3d prior =
        track.state == State::kActive ? track.filter.position() : track.reference;
    if (rigid_.Predict(slot, prior, match->measured, match->position_of_slot, &match->rigid_position[slot])) {
      match->has_rigid[slot] = 1;
      track.reference = match->rigid_position[slot];
    }
  }
}

// 4. The global second search: confirmed tracks still without a point (around the rigid
// model's position if any, else their prediction, within the wide gate) and lost tracks
// (around where the model or their last sighting puts them) against the points left over.
void Tracker::SearchWide(const std::vector<ReconstructedPoint>& points, FrameMatch* match) {
  const int num_slots = static_cast<int>(tracks_.size());
  search_.Clear();
  for (int slot = 0; slot < num_slots; ++slot) {
    const Track& track = tracks_[slot];
    if (match->point_of_slot[slot] >= 0) continue;
    if (track.state == State::kActive) {
      search_.Add(slot,
                  match->has_rigid[slot]
                      ? match->rigid_position[slot]
                      : Eigen::Vector3d(track.filter.position() + NeighbourInnovation(slot, match->measured,
                                                                                      match->position_of_slot, 3, 400.0)),
                  options_.wide_gate_mm);
    } else if (track.state == State::kLost) {
      search_.Add(slot, track.reference, options_.reacquire_gate_mm);
    }
  }
  std::vector<int>& before = wide_before_;
  before = match->point_of_slot;
  AssignByDistance(search_, points, &match->point_of_slot, &match->point_taken);
  for (int slot : search_.slots) match->found_wide[slot] = before[slot] < 0 && match->point_of_slot[slot] >= 0;
  for (int slot = 0; slot < num_slots; ++slot) {
    const int p = match->point_of_slot[slot];
    if (match->moved[slot] && p >= 0 &&
        (points[p].point_in_world - tracks_[slot].filter.position()).norm() > GateOf(tracks_[slot])) {
      match->found_wide[slot] = 1;
    }
  }
}

// 4b. Rigid clusters whose points the predictions permuted (a plate turning fast) get them back
// in the order their steady distances say; the filters of the tracks changed restart.
void Tracker::RepairRigidClusters(const std::vector<ReconstructedPoint>& points, FrameMatch* match) {
  const size_t num_slots = tracks_.size();
  swap_eligible_.assign(num_slots, 0);
  swap_changed_.assign(num_slots, 0);
  for (size_t slot = 0; slot < num_slots; ++slot) swap_eligible_[slot] = tracks_[slot].state == State::kActive;
  held_before_ = match->point_of_slot;
  const int repaired = swaps_.Resolve(rigid_, swap_eligible_, points, &match->point_of_slot, &swap_changed_);
  stats_.cluster_repairs += repaired;
  if (repaired == 0) return;
  // A cluster gathered again may leave a point it held to nobody: free for the births. A track
  // whose point a cluster took back was following another marker: it is lost (no rigid-model
  // samples from links it learned on the wrong marker) until it is found again.
  for (size_t slot = 0; slot < num_slots; ++slot) {
    if (held_before_[slot] < 0 || held_before_[slot] == match->point_of_slot[slot]) continue;
    match->point_taken[held_before_[slot]] = 0;
    if (match->point_of_slot[slot] < 0 && tracks_[slot].state == State::kActive) tracks_[slot].state = State::kLost;
  }
  // Every changed track holds a point now (freed above if it held another).
  for (size_t slot = 0; slot < num_slots; ++slot) {
    if (!swap_changed_[slot]) continue;
    match->point_taken[match->point_of_slot[slot]] = 1;
    match->moved[slot] = 1;
    match->found_wide[slot] = 1;
  }
}

// 5. Measurement updates.
void Tracker::ApplyMeasurements(uint64_t frame_number, const std::vector<ReconstructedPoint>& points,
                                const FrameMatch& match, std::vector<TrackSample>* samples) {
  const int num_slots = static_cast<int>(tracks_.size());
  const double noise = options_.kalman.measurement_noise_mm;
  std::vector<int>& rigid_slots = rigid_slots_;
  std::vector<Eigen::Vector3d>& rigid_positions = rigid_positions_;
  rigid_slots.clear();
  rigid_positions.clear();
  for (int slot = 0; slot < num_slots; ++slot) {
    Track& track = tracks_[slot];
    const int p = match.point_of_slot[slot];
    if (p < 0) continue;
    const Eigen::Vector3d& point = points[p].point_in_world;
    if (track.state == State::kLost) {
      // The coasted velocity is stale after a long loss: restart the filter at the point.
      track.filter = ConstantVelocityKalman(point, options_.kalman);
      track.filter_frame = frame_number;
      track.state = State::kActive;
      ++stats_.reacquisitions;
    } else if (match.found_wide[slot]) {
      // The prediction missed this point by more than its gate: its velocity is wrong, and a
      // Kalman update would only half-correct it and ring (two neighbouring markers would then
      // trade places every frame). Restart from the measured displacement instead.
      const double frames = static_cast<double>(frame_number - track.last_measured);
      const Eigen::Vector3d velocity =
          (point - track.last_point) * (options_.rate_hz / std::max(1.0, frames));
      track.filter.Restart(point, velocity, options_.kalman);
      track.filter_frame = frame_number;
    } else {
      track.filter.Update(point, noise);
    }
    track.last_point = point;
    track.last_measured = frame_number;
    track.held = 0;
    track.reference = track.filter.position();
    ++track.hits;
    ++track.age;
    if (track.state == State::kTentative) {
      track.history.emplace_back(frame_number, track.filter.position());
      track.min_views = std::min(track.min_views, points[p].num_views);
      if (track.hits >= BirthFramesOf(track)) Promote(&track, samples);
      continue;
    }
    // The triangulated point itself: the filter's estimate lags a hard-accelerating marker.
    TrackSample sample = SampleOf(track, frame_number, SampleKind::kMeasured);
    sample.position = point;
    samples->push_back(sample);
    rigid_slots.push_back(slot);
    rigid_positions.push_back(point);
  }
  rigid_.Update(rigid_slots, rigid_positions);
}

// 6. Tracks without a point this frame: tentative ones die, active ones continue on the rigid
// model or coast (not counting a drop-out's frames) and get lost, lost ones wait for
// reacquisition and then are freed.
void Tracker::HandleUnmeasured(uint64_t frame_number, const FrameMatch& match, std::vector<TrackSample>* samples) {
  const int num_slots = static_cast<int>(tracks_.size());
  const double noise = options_.kalman.measurement_noise_mm;
  const uint64_t max_predicted = static_cast<uint64_t>(std::lround(options_.max_predicted_s * options_.rate_hz));
  const uint64_t coast = static_cast<uint64_t>(std::lround(options_.coast_s * options_.rate_hz));
  const uint64_t reacquire = static_cast<uint64_t>(std::lround(options_.reacquire_s * options_.rate_hz));
  const uint64_t hold = static_cast<uint64_t>(std::lround(options_.dropout_hold_s * options_.rate_hz));
  // Frames without a frame set since the last Update measured nothing; this one measured nothing
  // when no confirmed track holds a point.
  const uint64_t skipped = updated_ && frame_number > last_update_frame_ ? frame_number - last_update_frame_ - 1 : 0;
  bool dropout = true;
  for (int slot = 0; slot < num_slots && dropout; ++slot) {
    dropout = !(match.point_of_slot[slot] >= 0 && tracks_[slot].state == State::kActive);
  }
  const uint64_t dropout_frames = skipped + (dropout ? 1 : 0);
  updated_ = true;
  last_update_frame_ = frame_number;
  for (int slot = 0; slot < num_slots; ++slot) {
    Track& track = tracks_[slot];
    if (track.state == State::kFree || match.point_of_slot[slot] >= 0) continue;
    if (track.state == State::kActive) track.held = std::min(hold, track.held + dropout_frames);
    const uint64_t missing = frame_number - track.last_measured - track.held;
    if (track.state == State::kTentative) {
      FreeTrack(slot);
      continue;
    }
    if (track.state == State::kActive) {
      track.hits = 0;
      if (match.has_rigid[slot] && missing <= max_predicted) {
        // Seed 001 section 5.2: the model's position stands in for the measurement.
        track.filter.Update(match.rigid_position[slot], 3.0 * noise);
        samples->push_back(SampleOf(track, frame_number, SampleKind::kPredicted));
        ++stats_.predicted_samples;
      } else if (missing > coast) {
        track.state = State::kLost;
      }
      continue;
    }
    if (missing > reacquire) FreeTrack(slot);
  }
}

// 7. New tentative tracks from the points no track took, seen by enough cameras.
void Tracker::BirthTracks(uint64_t frame_number, const std::vector<ReconstructedPoint>& points,
                          const FrameMatch& match, std::vector<TrackSample>* samples) {
  born_.clear();
  for (int p = 0; p < static_cast<int>(points.size()); ++p) {
    if (match.point_taken[p] || points[p].num_views < options_.birth_min_views) continue;
    const int slot = NewTrack(frame_number, points[p].point_in_world);
    born_.emplace_back(p, slot);
    Track& track = tracks_[slot];
    track.hits = 1;
    track.age = 1;
    track.min_views = points[p].num_views;
    track.history.emplace_back(frame_number, points[p].point_in_world);
    if (track.hits >= BirthFramesOf(track)) Promote(&track, samples);
  }
}

}  // namespace mocap
