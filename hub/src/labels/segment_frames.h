// Where a segment's markers sit in a frame built from its neighbours: which of a cluster's names
// each of its points carries when the cluster's own distances cannot tell (another subject's
// markers sit elsewhere on the limb, so a near-symmetric triangle's sides differ by up to half).
// The segment's orientation is taken from the directions to two anchors, the neighbouring
// segments (or loose markers) nearest it and steadiest with it in the set (for a shank: the thigh
// cluster and the foot), whose centroids do not depend on how their own names are permuted; the
// set's mean shape of the segment, turned into that frame, is matched to the points. The anchors
// fix the segment's orientation but for how far a long bone turns about its own axis (the
// direction to its first anchor): names of a segment laid out along that axis that differ only by
// such a turn (two wrist markers and the forearm's pronation, which differs between activities)
// are never decided here. Segments of fewer than three markers are not decided either (a pair
// swapped is a half turn about an axis the anchors cannot see). Pure.
#pragma once

#include <utility>
#include <vector>

#include <Eigen/Core>

#include "labels/marker_set.h"

namespace mocap {

struct SegmentAnchors {
  int segment = -1;
  std::vector<int> anchor[2];                        // marker indices of each anchor (a segment or a loose marker)
  Eigen::Vector3d limb_axis = Eigen::Vector3d::Zero();  // unit, mean shape: centroid -> first anchor's centroid
  // The segment's markers run along its limb axis (spread across it less than half as far as
  // along it: elbow and wrist markers on a forearm): such a segment turns about that axis as far
  // as the activity turns the limb (pronation), so names told apart only by that turn are never
  // decided by the anchors. A cluster spread around a limb (a thigh plate) does not qualify.
  bool along_limb = false;
};

// The segments that can be decided (three or more markers placed in the mean shape, two anchors
// whose directions differ by at least 25 degrees), with their anchors: each other segment or
// loose marker scored by its mean distance to the segment plus 10 times the mean sd of those
// distances (near and steady: across one joint), the best two taken.
std::vector<SegmentAnchors> ChooseSegmentAnchors(const MarkerSet& set);

// Whether giving the segment's names by `relabel` (pairs old name -> new name, all in the segment,
// a permutation of the names they mention) is only a turn of a segment laid out along its limb
// (`along_limb`) about the limb's axis (within 30 degrees of it): what the anchors cannot decide.
bool IsTurnAboutLimb(const MarkerSet& set, const SegmentAnchors& anchors, const std::vector<std::pair<int, int>>& relabel);

// One frame: `labels` per point (-1: none). For each decidable segment whose every member and
// every anchor member is labelled in this frame, each member point's vote: the segment name its
// place in the anchors' frame is nearest (one to one). `votes` per point, -1 where none.
void VoteInSegmentFrames(const MarkerSet& set, const std::vector<SegmentAnchors>& anchors,
                         const std::vector<Eigen::Vector3d>& points, const std::vector<int>& labels,
                         std::vector<int>* votes);

}  // namespace mocap
