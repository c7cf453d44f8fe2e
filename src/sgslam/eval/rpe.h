// Relative pose error as TUM's evaluate_rpe.py computes it with
// `--fixed_delta --delta_unit s`: pairs of estimate poses `delta` apart, each
// compared with the ground-truth motion between the gt poses nearest in time.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "sgslam/common/time.h"
#include "sgslam/eval/stats.h"
#include "sgslam/io/trajectory.h"

namespace sgslam::eval {

// More pairs than this are thinned (the script samples them at random).
constexpr std::size_t kRpeMaxPairs = 10000;

// evaluate_rpe.py's find_closest_index, a binary search that only considers the
// elements it visits (and index 0); ties keep the first visited. sorted must be
// ascending and non-empty.
std::size_t FindClosestIndex(const std::vector<Timestamp>& sorted, Timestamp t);

struct RpePair {
  std::size_t est0, est1, gt0, gt1;  // indices into the trajectories
  double trans = 0;                  // metres
  double rot_deg = 0;                // degrees
};

struct RpeResult {
  Timestamp delta = 0;
  ErrorStats trans;    // metres
  ErrorStats rot_deg;  // degrees
  std::vector<RpePair> pairs;
  bool thinned = false;  // more than kRpeMaxPairs candidate pairs existed
};

// gt and est sorted by time with unique stamps. Throws InputError (naming gt_name
// and est_name) when fewer than 2 estimate stamps overlap the ground truth or
// fewer than 2 pairs remain.
RpeResult ComputeRpe(const Trajectory& gt, const Trajectory& est, Timestamp delta,
                     const std::string& gt_name = "ground truth", const std::string& est_name = "estimate");

}  // namespace sgslam::eval
