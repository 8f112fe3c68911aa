// Rigid-pair links and sphere-intersection prediction.
#include "track/rigid_model.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "util/running_variance.h"

namespace mocap {

RigidModel::RigidModel(const RigidModelOptions& options) : options_(options) { options_.Check(); }

void RigidModel::EnsureCapacity(int slot) {
  if (slot < capacity_) return;
  const int capacity = std::max(slot + 1, capacity_ * 2);
  std::vector<RigidLink> grown(static_cast<size_t>(capacity) * capacity);
  std::vector<unsigned char> grown_state(grown.size(), kUnlinked);
  for (int a = 0; a < capacity_; ++a) {
    for (int b = a + 1; b < capacity_; ++b) {
      grown[static_cast<size_t>(a) * capacity + b] = links_[Index(a, b)];
      grown_state[static_cast<size_t>(a) * capacity + b] = state_[Index(a, b)];
    }
  }
  links_.swap(grown);
  state_.swap(grown_state);
  capacity_ = capacity;
}

void RigidModel::ResetSlot(int slot) {
  if (slot >= capacity_) return;
  for (int other = 0; other < capacity_; ++other) {
    if (other == slot) continue;
    At(slot, other) = RigidLink();
    state_[Index(slot, other)] = kUnlinked;
  }
}

void RigidModel::Update(const std::vector<int>& slots, const std::vector<Eigen::Vector3d>& positions) {
  for (int slot : slots) EnsureCapacity(slot);
  const double max_variance = options_.max_std_mm * options_.max_std_mm;
  const double max_link_distance_mm = options_.max_link_distance_mm, max_deviation_mm = options_.max_deviation_mm;
  // Pairs never linked whose squared distance is over this are certainly beyond
  // max_link_distance_mm (a margin of 1e-9 over rounding): most pairs of a subject, and they
  // skip the square root.
  const double far_squared = options_.max_link_distance_mm * options_.max_link_distance_mm * (1.0 + 1e-9);
  // Plain pointers and counts: the state bytes written below could alias the vectors' own
  // members, which the loop would otherwise load again on every pair.
  const size_t count = slots.size();
  const int* slot = slots.data();
  const Eigen::Vector3d* position = positions.data();
  unsigned char* states = state_.data();
  RigidLink* links = links_.data();
  const size_t capacity = static_cast<size_t>(capacity_);
  for (size_t i = 0; i < count; ++i) {
    for (size_t j = i + 1; j < count; ++j) {
      // The state byte first: most pairs are broken, or never linked and far apart, and their
      // links are not read.
      const size_t a = static_cast<size_t>(slot[i]), b = static_cast<size_t>(slot[j]);
      const size_t index = a < b ? a * capacity + b : b * capacity + a;
      unsigned char& state = states[index];
      if (state == kBroken) continue;
      const Eigen::Vector3d offset = position[i] - position[j];
      if (state == kUnlinked && offset.squaredNorm() > far_squared) continue;
      RigidLink& link = links[index];
      const double distance = offset.norm();
      if (link.samples == 0) {
        if (distance > max_link_distance_mm) continue;
      } else if (std::abs(distance - link.mean) > max_deviation_mm) {
        link.broken = true;
        state = kBroken;
        continue;
      }
      AddToRunningVariance(distance, &link.samples, &link.mean, &link.m2);
      state = kHolds;
      if (link.samples >= 5 && link.Variance() > max_variance) {
        link.broken = true;
        state = kBroken;
      }
    }
  }
}

bool RigidModel::Predict(int slot, const Eigen::Vector3d& prior, const std::vector<char>& measured,
                         const std::vector<Eigen::Vector3d>& position_of_slot,
                         Eigen::Vector3d* predicted) const {
  if (slot >= capacity_) return false;
  struct Candidate {
    int other;
    const RigidLink* link;
  };
  std::vector<Candidate> candidates;
  const int limit = std::min(capacity_, static_cast<int>(measured.size()));
  for (int other = 0; other < limit; ++other) {
    if (other == slot || !measured[other]) continue;
    const RigidLink& link = links_[Index(slot, other)];
    if (link.broken || link.samples < options_.min_samples) continue;
    candidates.push_back({other, &link});
  }
  if (static_cast<int>(candidates.size()) < options_.min_links_used) return false;
  // Seed: the longest-kept, steadiest links first.
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
    if (a.link->samples != b.link->samples) return a.link->samples > b.link->samples;
    return a.link->Variance() < b.link->Variance();
  });
  candidates.resize(std::min<size_t>(candidates.size(), options_.max_links_used));

  // min sum (|p - c_i| - d_i)^2 + damping |p - prior|^2 by Gauss-Newton from the prior; the small
  // damping only picks, among the exact solutions, the one nearest the prior.
  const double damping = 1e-3;
  Eigen::Vector3d p = prior;
  double sum_squares = 0.0;
  for (int iteration = 0; iteration < 15; ++iteration) {
    Eigen::Matrix3d normal = damping * Eigen::Matrix3d::Identity();
    Eigen::Vector3d gradient = damping * (p - prior);
    sum_squares = 0.0;
    for (const Candidate& c : candidates) {
      const Eigen::Vector3d offset = p - position_of_slot[c.other];
      const double length = offset.norm();
      if (length < 1e-9) return false;
      const Eigen::Vector3d direction = offset / length;
      const double residual = length - c.link->mean;
      sum_squares += residual * residual;
      normal.noalias() += direction * direction.transpose();
      gradient.noalias() += direction * residual;
    }
    const Eigen::Vector3d step = normal.ldlt().solve(gradient);
    if (!step.allFinite()) return false;
    p -= step;
    if (step.squaredNorm() < 1e-6) break;
  }
  // Spheres that do not meet (the links no longer describe this pose) give no prediction.
  if (std::sqrt(sum_squares / candidates.size()) > options_.max_deviation_mm) return false;
  *predicted = p;
  return true;
}

int RigidModel::NumActiveLinks() const {
  int count = 0;
  for (int a = 0; a < capacity_; ++a) {
    for (int b = a + 1; b < capacity_; ++b) {
      const RigidLink& link = links_[Index(a, b)];
      if (link.samples > 0 && !link.broken) ++count;
    }
  }
  return count;
}

}  // namespace mocap
