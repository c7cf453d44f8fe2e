// Absolute trajectory error as TUM's evaluate_ate.py defines it: poses associated
// by timestamp (associate.py), estimate positions rigidly aligned to the ground
// truth with Horn's closed form (no scale; geometry::AlignRigid), error =
// |R * p_est + t - p_gt| per pair.
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "sgslam/common/se3.h"
#include "sgslam/common/time.h"
#include "sgslam/eval/stats.h"
#include "sgslam/io/trajectory.h"

namespace sgslam::eval {

struct AteResult {
  ErrorStats stats;                                    // over errors, in metres
  SE3 T_gt_est;                                        // maps estimate positions into the gt world
  std::vector<std::pair<std::size_t, std::size_t>> pairs;  // (gt index, est index), by gt time
  std::vector<double> errors;                          // one per pair, metres
};

// gt and est sorted by time with unique stamps (UniqueStamps in evaluate.h). The names are only used in
// error messages (normally the file paths). Throws InputError when a trajectory is
// empty, nothing associates within max_difference, or fewer than 3 pairs do.
AteResult ComputeAte(const Trajectory& gt, const Trajectory& est, Timestamp max_difference,
                     const std::string& gt_name = "ground truth", const std::string& est_name = "estimate");

// The same at an alignment fitted elsewhere. Frames localised in a map are
// measured at the alignment fitted on the frames that made the map: one of their
// own would absorb an offset between them and the map. Needs one pair.
AteResult ComputeAteAt(const Trajectory& gt, const Trajectory& est, const SE3& T_gt_est, Timestamp max_difference,
                       const std::string& gt_name = "ground truth", const std::string& est_name = "estimate");

}  // namespace sgslam::eval
