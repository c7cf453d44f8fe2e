// The camera motion between the previous and the current frame from the flow pairs
// alone, for the RGB-D check (depth_check.h): the previous points are lifted with
// the previous depth and a PnP RANSAC (3D-2D) finds T_cur_prev. Unlike the
// tracker's constant-velocity prediction it follows jerky hand-held motion, and
// unlike F it is not degenerate under rotation, so a point moving along its
// epipolar line (the paper's blind spot) does not fit it.
//
// Coordinates: depth is sampled at the raw (distorted) previous positions, as TUM
// registers depth to the raw colour image; the geometry uses undistorted pixels.
// The PnP itself is geometry::SolvePnP.
// Thread safety: a free function on const inputs.
#pragma once

#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "sgslam/common/se3.h"
#include "sgslam/dynamic/depth_check.h"

namespace sgslam::dynamic {

// Fewer PnP inliers than this: no motion, and no RGB-D check this frame (a motion
// fitted on few points is not trusted to judge the others; not measured on its own).
constexpr int kMotionMinInliers = 30;

struct MotionEstimate {
  SE3 T_cur_prev;   // maps previous-camera points into the current camera
  int pairs = 0;    // pairs with a valid previous depth the estimate was fitted on
  int inliers = 0;  // within the PnP threshold (motion.cpp) after the refit
};

// prev_raw: previous positions as tracked (px, for the depth lookup); prev_un,
// cur_un: the same pairs undistorted. use[i]: pair i may take part; only previous
// depths within [kDepthMin, kDepthMax] (depth_check.h) count. nullopt when fewer
// than kMotionMinInliers pairs support a model.
std::optional<MotionEstimate> EstimateMotion(const std::vector<cv::Point2f>& prev_raw,
                                             const std::vector<cv::Point2f>& prev_un,
                                             const std::vector<cv::Point2f>& cur_un, const std::vector<bool>& use,
                                             const cv::Mat& prev_depth, double depth_factor, const Pinhole& K);

}  // namespace sgslam::dynamic
