// Labelling a whole recording by a subject model (`--labeller subject` of reconstruct and labels
// apply; trial_labeller.h is the default) from a marker set, in time linear in its frames (no
// search over the whole trial, no budget that runs out). Names belong to runs: a column's unbroken
// stretch of frames. Stages (one method each in SubjectLabeller):
//  1. Initialise: the first frames in which the set is seen nearly whole (at least as many points
//     as the set places, less init_missing_share of them: a marker never seen stays unnamed) are
//     fitted one by one (set_fit.h: the mean shape upright with the subject's scale, each segment
//     turned rigidly onto its points); a run takes a name when init_agreement of the fitted
//     frames it is in (three at least) gave it that name. Where too few names agree, later frames
//     are tried; a window of fewer than three fitted frames is none.
//  2. The subject's own model, kept from then on: the distance of every pair of names as this
//     subject holds it (mean and sd over the frames both were named), and per name where its
//     partners stood the last frame all were named. A pair is steady when its own sd is small:
//     these pairs, not the set's (another person's proportions), judge this subject.
//  3. Forward from the initialisation to the end, then backward to the start, frame by frame: a
//     named run that jumps (farther than jump_mm from where its name's last two frames put it,
//     with another point at half that distance: the tracker joined two markers) loses the name
//     from there; a named point that breaks most of its steady pairs loses its name in that frame (the worst
//     first), and its run loses the name from where it broke after `break_frames` such frames in a
//     row (a swap: the rest of the run becomes a run of its own); a name no run holds is placed by
//     its steady partners (a rigid fit of where they stood), or where it was last seen for a short
//     time, and given to the nearest unnamed point within the gate, unless another point or name
//     comes near (never a coin toss) or its steady pairs break. Names that cannot be placed so
//     (never named, no steady partners) come from the set's shape placed on the names given
//     (every refit_frames frames while some are missing; a run takes one when refit_confirm fits
//     agree with no other name between). The run takes the name for the
//     frames already passed where it keeps its pairs and the name is free.
// A name is never held by two runs at once. Every decision is one line in `decisions`.
// Pure.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "io/marker_trajectories.h"
#include "labels/marker_set.h"
#include "labels/set_fit.h"

namespace mocap {

struct SubjectLabellerOptions {
  int up_axis = -1;                // the data's vertical axis (0-2, positive up); -1: detected
  SetFitOptions fit;               // the initialisation's fit of each frame
  int init_frames = 5;             // frames fitted at the initialisation
  int init_spacing = 10;           // frames between them
  double init_agreement = 1.0;     // of the fitted frames a run is in that must give it one name
  int init_attempts = 20;          // later windows tried when too few names agree
  double init_min_share = 0.8;     // of the set's shape markers named for an initialisation to stand
  double init_missing_share = 0.1; // of the set's shape markers an initialisation frame may lack (seen nearly whole)
  double partner_gate_mm = 25.0;   // a name placed by its partners: points this near
  double hold_gate_mm_per_frame = 6.0;  // a name placed where it was last seen: widened per frame since
  int hold_frames = 30;            // how long a name's last position places it
  double ambiguity_ratio = 2.0;    // the next nearest point or name at least this much farther...
  double margin_mm = 10.0;         // ...and this much
  double steady_sd_mm = 6.0;       // a pair whose own sd is at most this is steady (partners, checks)
  double max_pair_mm = 600.0;      // farther pairs are not partners
  double break_mm = 12.0;          // a steady pair breaks beyond this plus 4 sd of its own mean
  int break_frames = 3;            // a named run breaking this many frames in a row loses its name
  int refit_frames = 10;           // the set's shape placed again this often while names are missing
  int refit_confirm = 4;           // fits in a row that must agree on a run's name
  double refit_gate_mm = 60.0;     // a refit names points this near their placed marker (few compete then)
  double jump_mm = 100.0;          // a named point this far from its name's constant-velocity prediction: a jump
  int min_pair_frames = 10;        // frames a pair was seen named before it is known
  size_t max_decisions = 100000;   // log lines kept (the count goes on)
  void Check() const;              // throws std::invalid_argument naming the field
};

struct SubjectLabelling {
  MarkerTrajectories named;
  size_t runs = 0;          // unbroken runs of the input's columns (split where they broke)
  size_t named_runs = 0;    // of those, the ones given a name
  size_t names_placed = 0;  // marker-set names that hold data
  size_t named_points = 0, points = 0;
  size_t frame_names_dropped = 0;  // points of named runs left unnamed in a frame that broke their pairs
  long init_frame = -1;            // first frame of the initialisation (frame index), -1: none
  size_t init_names = 0;           // names the initialisation gave
  size_t decisions_made = 0;       // all decisions (decisions holds the first max_decisions)
  std::vector<std::string> decisions;
};

// Throws std::invalid_argument for bad options or a marker set that cannot label.
SubjectLabelling LabelSubject(const MarkerTrajectories& anonymous, const MarkerSet& set,
                                 const SubjectLabellerOptions& options = {});

}  // namespace mocap
