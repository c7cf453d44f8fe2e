// Motion-only bundle adjustment for tracking, with the semantics of ORB-SLAM2's
// Optimizer::PoseOptimization: `rounds` Levenberg-Marquardt runs of
// `iterations` each; after every run each observation is classified by its
// chi2 at the current estimate (excluded ones too) and outliers sit out the
// next run; Huber kernels (delta = sqrt(chi2 threshold)) in all but the last
// run. Stops early when fewer than 10 inliers remain.
//
// Two flags let a caller decide which observations set the pose
// (tracking/trusted_pose.h): a classify_only observation is classified at every
// round but never fitted; a start_excluded one sits out the first run only, like
// an outlier of a previous classification, and comes back when it fits.
//
// Map-agnostic: the caller fills plain observations. Deterministic (one thread,
// fixed order). Pure function, safe to call from any thread.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "sgslam/common/se3.h"
#include "sgslam/optim/cost_functions.h"

namespace sgslam::optim {

struct PoseObservation {
  Eigen::Vector3d p_w = Eigen::Vector3d::Zero();  // map point [m], held fixed
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();   // keypoint [px]
  double u_right = -1;                            // virtual right u [px]; < 0: monocular
  double inv_sigma2 = 1;                          // 1 / sigma^2 of the keypoint's level
  bool classify_only = false;                     // classified at the pose, never fitted
  bool start_excluded = false;                    // not fitted in the first run (may come back)
};

struct PoseOptimizerOptions {
  int rounds = 4;              // classify-and-reoptimise runs
  int iterations = 10;         // LM iterations per run
  double chi2_mono = 5.991;    // 95 % of chi2 with 2 dof
  double chi2_stereo = 7.815;  // 95 % of chi2 with 3 dof
};

struct PoseOptimizationResult {
  SE3 T_c_w;                 // world -> camera
  std::vector<bool> inlier;  // one per observation, from the final classification
  int inliers = 0;
};

// With fewer than 3 usable observations (in front of the camera) the pose is
// returned unchanged and only classified.
PoseOptimizationResult OptimizePose(const SE3& T_c_w_initial, const std::vector<PoseObservation>& obs,
                                    const Intrinsics& K, const PoseOptimizerOptions& options = {});

}  // namespace sgslam::optim
