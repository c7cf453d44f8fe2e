// Local mapping (ORB-SLAM2's settings unless a comment says otherwise).
#pragma once

#include "sgslam/common/config_checker.h"

namespace sgslam {

struct MappingConfig {
  int triangulation_neighbours = 10;  // covisible keyframes searched for new points
  int fusion_neighbours = 10;         // covisible keyframes (and theirs) for duplicate fusion
  int ba_first_iterations = 5;        // local BA, with robust kernel
  int ba_second_iterations = 10;      // local BA, after removing outliers
  // Free keyframes of local BA: the new one and its best covisibles. The Schur
  // complement grows with their square, and in a small scene every keyframe is
  // covisible with every other.
  int ba_max_local_keyframes = 25;
  double redundant_ratio = 0.9;  // a keyframe is culled when this share of its points is seen thrice elsewhere
  int queue_size = 3;            // keyframes waiting for local mapping, beyond which tracking waits
  // Frames after a keyframe during which local mapping counts as busy for the
  // keyframe decision (ORB-SLAM2's "idle" rule). --sequential steps the mapper at
  // once, so it always waits this long; in parallel, a keyframe due later
  // interrupts a running BA, as ORB-SLAM2's InterruptBA does.
  int busy_frames = 5;
  // One bundle adjustment of the whole map when the sequence ends (what ORB-SLAM2
  // runs after a loop closure), iterations per stage; 0: off. Only trajectory.txt
  // and the maps see it; trajectory_online.txt is what tracking output at the time.
  int final_ba_iterations = 10;
  // A bound on the map's size for long runs in one place (a robot's patrol): once
  // the map holds this many keyframes it stops growing and later frames are tracked
  // in it, as with --localize. 0: no bound.
  int max_keyframes = 0;

  template <class V>
  void Visit(V&& v) {
    v("triangulation_neighbours", triangulation_neighbours, "keyframes searched for new points");
    v("fusion_neighbours", fusion_neighbours, "keyframes searched for duplicates");
    v("ba_first_iterations", ba_first_iterations, "local BA iterations with robust kernel");
    v("ba_second_iterations", ba_second_iterations, "local BA iterations after outlier removal");
    v("ba_max_local_keyframes", ba_max_local_keyframes, "free keyframes in local BA, best covisibles first");
    v("redundant_ratio", redundant_ratio, "share of points seen elsewhere to cull a keyframe");
    v("queue_size", queue_size, "keyframes queued for local mapping");
    v("busy_frames", busy_frames, "frames after a keyframe that mapping counts as busy; later keyframes interrupt its BA");
    v("final_ba_iterations", final_ba_iterations, "global BA iterations per stage when the sequence ends; 0: off");
    v("max_keyframes", max_keyframes, "keyframes at which the map stops growing and frames are only tracked in it; 0: no bound");
  }
  void Validate(ConfigChecker& c) const;
};

}  // namespace sgslam
