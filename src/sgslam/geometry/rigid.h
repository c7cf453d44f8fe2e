// Rigid (SE(3), no scale) alignment of 3-D point sets: Horn's closed form, and
// the loop-verification solver built on it, ORB-SLAM2's Sim3Solver for RGB-D
// (scale fixed at 1, as ORB-SLAM2 does when depth is known).
//
// EstimateRigidRansac: RANSAC on minimal sets of 3 correspondences, each solved
// by AlignRigid; a correspondence is an inlier of T_12 when p_c2 mapped by T_12
// reprojects onto uv1 AND p_c1 mapped by T_21 onto uv2, each within its own
// squared pixel threshold (Sim3Solver::CheckInliers) and in front of the camera.
// Sampling stops once `probability` of having drawn an all-inlier set is reached
// for the best inlier ratio so far (never assumed below min_inliers / N, as
// ORB-SLAM2's SetRansacParameters). The winner is refitted on all its inliers
// (weighted, see rigid.cpp) and reclassified.
// Deterministic: the samples come from std::mt19937 seeded by the options (and
// libstdc++'s uniform_int_distribution). Thread safety: free functions on const inputs.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <vector>

#include "sgslam/common/se3.h"
#include "sgslam/geometry/pinhole.h"

namespace sgslam::geometry {

// Horn / Umeyama without scale: the rigid T_data_model minimising
// sum w_i |T * model[i] - data[i]|^2. Both lists must have the same size >= 1;
// weights: one >= 0 per pair (not all 0), or empty for w_i = 1.
SE3 AlignRigid(const std::vector<Eigen::Vector3d>& model, const std::vector<Eigen::Vector3d>& data,
               const std::vector<double>& weights = {});

// One match between keyframe 1 and keyframe 2 (undistorted pixels).
struct RigidCorrespondence {
  Eigen::Vector3d p_c1 = Eigen::Vector3d::Zero();  // the point in camera 1 [m]
  Eigen::Vector3d p_c2 = Eigen::Vector3d::Zero();  // the point in camera 2 [m]
  Eigen::Vector2d uv1 = Eigen::Vector2d::Zero();   // its keypoint in image 1 [px]
  Eigen::Vector2d uv2 = Eigen::Vector2d::Zero();   // its keypoint in image 2 [px]
  double max_sq_error1 = 9.210;                    // [px^2] in image 1; ORB-SLAM2: 9.210 * sigma^2 of the level
  double max_sq_error2 = 9.210;                    // [px^2] in image 2
};

struct RigidRansacProblem {
  std::vector<RigidCorrespondence> matches;
  Pinhole K1, K2;
};

// ORB-SLAM2's LoopClosing: SetRansacParameters(0.99, 20, 300).
struct RigidRansacOptions {
  int max_iterations = 300;
  int min_inliers = 20;       // fewer: no transform
  double probability = 0.99;  // of drawing one all-inlier sample before stopping
  std::uint32_t seed = 0;     // of the sampling generator
};

struct RigidRansacResult {
  SE3 T_12;                  // camera 2 -> camera 1: p_c1 = T_12 * p_c2
  std::vector<bool> inlier;  // one per match
  int inliers = 0;
  int iterations = 0;  // RANSAC samples drawn
};

// nullopt with fewer than 3 matches or fewer than min_inliers inliers.
std::optional<RigidRansacResult> EstimateRigidRansac(const RigidRansacProblem& problem,
                                                     const RigidRansacOptions& options = {});

}  // namespace sgslam::geometry
