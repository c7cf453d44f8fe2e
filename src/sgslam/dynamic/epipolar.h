// Algorithm 1 line 3 and eqs. (2)-(4): the fundamental matrix between the previous
// and the current frame, and the distance of a current point to the epipolar line
// of its previous match.
//
// Direction: F maps previous points to lines in the current image,
// x_cur^T F x_prev = 0 (eq. 3 with P1 = previous, P2 = current).
//
// Estimation: cv::findFundamentalMat(prev, cur, FM_RANSAC, ...). In OpenCV 4.6
// (modules/calib3d/src/fundam.cpp, cv::findFundamentalMat) FM_RANSAC with at least
// 15 pairs runs createRANSACPointSetRegistrator(cb, 7, ...), i.e. RANSAC on minimal
// sets of 7 pairs solved by run7Point (up to 3 solutions each), scored by the larger
// of the two point-to-epipolar-line distances; with 8-14 pairs it silently uses
// LMedS, with 7 the bare 7-point solver. RANSACPointSetRegistrator::run
// (modules/calib3d/src/ptsetreg.cpp) seeds its generator with RNG((uint64)-1) on
// every call, so the same pairs in the same order give the same F; the points are
// rounded to float and the winning model is a 7-point solution, not refitted.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "sgslam/common/se3.h"
#include "sgslam/dynamic/dynamic_config.h"

namespace sgslam::dynamic {

struct FundamentalEstimate {
  Eigen::Matrix3d F_cur_prev = Eigen::Matrix3d::Zero();  // x_cur^T F x_prev = 0, ||F|| = 1
  int pairs = 0;                                         // pairs the estimate was fitted on
  int inliers = 0;                                       // RANSAC inliers among them
  bool from_static = false;                              // fitted on the pairs outside dynamic boxes only
};

// prev, cur: matched pairs (px). preferred: pairs believed static (current point
// outside every dynamic box); F is fitted on them alone when at least
// config.min_static_pairs exist, else on all. nullopt when fewer than 8 pairs or
// when OpenCV finds no model.
std::optional<FundamentalEstimate> EstimateFundamental(const std::vector<Eigen::Vector2d>& prev,
                                                       const std::vector<Eigen::Vector2d>& cur,
                                                       const std::vector<bool>& preferred, const DynamicConfig& config);

// Eq. (4): d = |p_cur^T F p_prev| / sqrt(X^2 + Y^2), (X, Y, Z) = F p_prev (eq. 2).
double EpipolarDistance(const Eigen::Matrix3d& F_cur_prev, const Eigen::Vector2d& prev, const Eigen::Vector2d& cur);

// The F of a known relative pose: F = K^-T [t]x R K^-1 with (R, t) = T_cur_prev.
Eigen::Matrix3d FundamentalFromPose(const SE3& T_cur_prev, const Eigen::Matrix3d& K);

}  // namespace sgslam::dynamic
