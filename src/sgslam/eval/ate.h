// Absolute trajectory error as TUM's evaluate_ate.py defines it: poses associated
// by timestamp (associate.py), estimate positions rigidly aligned to the ground
// truth with Horn's closed form (no scale; geometry::AlignRigid), error =
// |R * p_est + t - p_gt| per pair.
#pragma once

#include <cstddef>
#include <optional>
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
// T_gt_est: a given alignment (a map's frame, fitted on the run that made the map:
// `sgslam eval --align-with`), used instead of fitting one to these poses.
AteResult ComputeAte(const Trajectory& gt, const Trajectory& est, Timestamp max_difference,
                     const std::string& gt_name = "ground truth", const std::string& est_name = "estimate",
                     const std::optional<SE3>& T_gt_est = std::nullopt);

}  // namespace sgslam::eval
