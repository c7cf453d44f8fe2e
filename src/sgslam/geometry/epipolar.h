// Two-view epipolar geometry: the fundamental matrix between two images, estimated
// from pixel pairs (the rejection's Algorithm 1 line 3) or from known poses (local
// mapping's triangulation search), and the distance of a point to the epipolar
// line of its match (eqs. (2)-(4) of the paper).
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
#include "sgslam/geometry/pinhole.h"

namespace sgslam::geometry {

struct FundamentalOptions {
  double threshold = 1.0;    // px, OpenCV's RANSAC epipolar distance
  double confidence = 0.99;  // probability
  int iterations = 1000;     // at most
  int min_preferred = 20;    // preferred pairs needed to fit on them alone
};

struct FundamentalEstimate {
  Eigen::Matrix3d F_cur_prev = Eigen::Matrix3d::Zero();  // x_cur^T F x_prev = 0, ||F|| = 1
  int pairs = 0;                                         // pairs the estimate was fitted on
  int inliers = 0;                                       // RANSAC inliers among them
  bool from_static = false;                              // fitted on the preferred pairs only
};

// prev, cur: matched pairs (px). preferred: pairs believed static (for the
// rejection: outside every dynamic box); F is fitted on them alone when at least
// options.min_preferred exist, else on all. nullopt when fewer than 8 pairs or
// when OpenCV finds no model.
std::optional<FundamentalEstimate> EstimateFundamental(const std::vector<Eigen::Vector2d>& prev,
                                                       const std::vector<Eigen::Vector2d>& cur,
                                                       const std::vector<bool>& preferred,
                                                       const FundamentalOptions& options);

// Eq. (4): d = |p_cur^T F p_prev| / sqrt(X^2 + Y^2), (X, Y, Z) = F p_prev (eq. 2).
double EpipolarDistance(const Eigen::Matrix3d& F_cur_prev, const Eigen::Vector2d& prev, const Eigen::Vector2d& cur);

// F_21 of known poses, x2^T F_21 x1 = 0 for pixels x1 in camera 1 and x2 in
// camera 2 with the same intrinsics: F_21 = K^-T [t_21]x R_21 K^-1 (not normalised).
Eigen::Matrix3d FundamentalMatrix(const SE3& T_21, const Pinhole& K);

}  // namespace sgslam::geometry
