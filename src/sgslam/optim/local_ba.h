// Local bundle adjustment with the semantics of ORB-SLAM2's
// Optimizer::LocalBundleAdjustment: Huber kernels for `first_iterations`; then,
// unless aborted, observations with chi2 above the threshold or a point behind
// the camera are dropped and the rest re-optimised for `second_iterations`
// without the kernel; the returned outlier flags come from a last chi2/depth
// test of every observation, so the caller can erase them from the map.
//
// Map-agnostic: the map code copies keyframe poses, points and observations in
// and writes the results back. Fixed keyframes (ORB-SLAM2's "fixed cameras"
// that see local points) are held constant; with none fixed the smallest id is
// fixed as the gauge. The abort hook is polled once per LM iteration (local
// mapping aborts when a new keyframe arrives); an aborted run keeps the last
// accepted iterate, like g2o's force-stop flag. Deterministic with threads = 1.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <vector>

#include "sgslam/common/se3.h"
#include "sgslam/optim/cost_functions.h"

namespace sgslam::optim {

struct BaKeyFrame {
  std::uint64_t id = 0;
  SE3 T_c_w;  // world -> camera
  bool fixed = false;
};

struct BaPoint {
  std::uint64_t id = 0;
  Eigen::Vector3d p_w = Eigen::Vector3d::Zero();  // [m]
};

struct BaObservation {
  int keyframe = -1;                             // index into BaProblem::keyframes
  int point = -1;                                // index into BaProblem::points
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();  // [px]
  double u_right = -1;                           // [px]; < 0: monocular
  double inv_sigma2 = 1;
};

struct BaProblem {
  std::vector<BaKeyFrame> keyframes;
  std::vector<BaPoint> points;
  std::vector<BaObservation> observations;
  Intrinsics intrinsics;
};

struct BaOptions {
  int first_iterations = 5;    // with Huber kernels
  int second_iterations = 10;  // inliers only, no kernel
  double chi2_mono = 5.991;
  double chi2_stereo = 7.815;
  int threads = 1;              // Ceres threads; bit-reproducibility is only tested with 1
};

struct BaResult {
  std::vector<SE3> T_c_w;            // one per keyframe
  std::vector<Eigen::Vector3d> p_w;  // one per point
  std::vector<bool> outlier;         // one per observation (invalid indices: true)
  bool aborted = false;
  int iterations = 0;       // LM iterations over both stages
  double initial_cost = 0;  // Ceres cost (1/2 sum rho(chi2)) before the first stage
  double final_cost = 0;    // Ceres cost after the last stage that ran
};

BaResult SolveLocalBa(const BaProblem& problem, const BaOptions& options,
                      const std::function<bool()>& should_abort = {});

}  // namespace sgslam::optim
