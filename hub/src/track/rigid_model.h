// The dynamic model of seed 001 section 5: links between pairs of tracked markers carrying the
// running mean and variance of their distance (eqs. 17-18, as Welford's update), broken for good
// when a distance strays from the mean or the spread grows (the pair is not rigid). A missing
// marker is placed at the given distances from its measured linked markers, the point nearest to
// its Kalman prediction: on the sphere (one link), on the spheres' circle (two, as in the seed),
// or at their intersection (three or more), solved as one damped least-squares problem.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "track/track_options.h"

namespace mocap {

// 24 bytes (the flag beside the count, not after the doubles): the update and the swap repair
// read a link for every pair of measured tracks every frame.
struct RigidLink {
  int samples = 0;
  bool broken = false;
  double mean = 0.0;
  double m2 = 0.0;  // sum of squared deviations (Welford)

  double Variance() const { return samples > 1 ? m2 / (samples - 1) : 0.0; }
};

class RigidModel {
 public:
  explicit RigidModel(const RigidModelOptions& options);

  // Slots are small integers naming tracks; a slot reset forgets all its links (its track ended
  // and the slot will name another).
  void ResetSlot(int slot);
  // Adds the distances between all markers measured this frame.
  void Update(const std::vector<int>& slots, const std::vector<Eigen::Vector3d>& positions);
  // Predicts slot's position from linked slots with measured[s] set this frame.
  bool Predict(int slot, const Eigen::Vector3d& prior, const std::vector<char>& measured,
               const std::vector<Eigen::Vector3d>& position_of_slot, Eigen::Vector3d* predicted) const;

  // nullptr when a and b never were linked. Inline: the swap repair asks it for every pair of
  // measured tracks every frame.
  const RigidLink* Link(int a, int b) const {
    if (a >= capacity_ || b >= capacity_ || a == b) return nullptr;
    const RigidLink& link = links_[Index(a, b)];
    return link.samples > 0 || link.broken ? &link : nullptr;
  }
  int NumActiveLinks() const;
  // Whether a and b are linked and the link holds (Link non-null and not broken), from one byte
  // per pair: the loops over every pair of measured tracks pass over the others without reading
  // their links.
  bool Holds(int a, int b) const {
    return a < capacity_ && b < capacity_ && a != b && state_[Index(a, b)] == kHolds;
  }

 private:
  void EnsureCapacity(int slot);
  RigidLink& At(int a, int b) { return links_[Index(a, b)]; }
  size_t Index(int a, int b) const {
    return a < b ? static_cast<size_t>(a) * capacity_ + b : static_cast<size_t>(b) * capacity_ + a;
  }

  // A link's state beside it, kept with every change of samples and broken.
  enum : unsigned char { kUnlinked = 0, kHolds = 1, kBroken = 2 };

  RigidModelOptions options_;
  int capacity_ = 0;
  std::vector<RigidLink> links_;  // capacity_ x capacity_, upper triangle used
  std::vector<unsigned char> state_;  // the same cells' states
};

}  // namespace mocap
