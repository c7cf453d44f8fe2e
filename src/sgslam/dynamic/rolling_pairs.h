// Flow pairs of a rolling-shutter camera moved to their frames' middle-row cameras
// (camera/rolling_shutter.h) before Algorithm 1 judges them.
//
// Why: F (eq. 4) and the PnP of the RGB-D check model each image as seen from one
// camera. A rolling shutter sees row v from the camera at t + tau(v); when the
// angular velocity changes between two frames (a hand-held turn speeding up or
// slowing down), the two images are bent differently, by (w_cur - w_prev) tau(v),
// which neither model can absorb. On the static fr1_rpy the motion fit then left
// static points 5-20 px off in the top or bottom rows of fast frames (median
// residual 5 px in frame 2), and the RGB-D check flagged them as moving.
//
// The previous frame's pairs are turned with the angular velocity the tracker
// settled on for that frame; the current one's is fitted here from the pairs
// themselves: a PnP RANSAC on the previous points lifted with their depth, then
// the pose and angular velocity together (optim/rolling_shutter_pose.h) on its
// inliers. Only the undistorted positions change; the raw ones (depth lookups,
// priors) stay as tracked.
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "sgslam/common/se3.h"
#include "sgslam/dynamic/depth_check.h"
#include "sgslam/dynamic/dynamic_config.h"
#include "sgslam/dynamic/rejection.h"

namespace sgslam::dynamic {

struct RollingShutterInput {
  double readout = 0;                                  // s, top to bottom row; 0: nothing to do
  int height = 0;                                      // px, raw image rows
  Eigen::Vector3d w_prev = Eigen::Vector3d::Zero();    // rad/s, camera frame, the previous frame's
  Eigen::Vector3d w_guess = Eigen::Vector3d::Zero();   // rad/s, the current frame's prediction
  cv::Mat prev_depth;                                  // as DepthCheckInput
  double depth_factor = 5000;
  Pinhole K;
};

struct RollingShutterFit {
  Eigen::Vector3d w_cur = Eigen::Vector3d::Zero();  // rad/s, the current frame's velocity used
  bool fitted = false;                              // false: w_guess was used (too few pairs)
  int pairs = 0;                                    // pairs with a previous depth, offered to the fit
  int inliers = 0;                                  // pairs the fit ran on
  SE3 T_cur_prev;  // the fitted motion between the middle-row cameras (valid when fitted)
};

// Turns pairs.prev_un with in.w_prev and pairs.cur_un with the fitted (or guessed)
// current velocity, in place. use[i]: pair i may take part in the fit (valid and
// preferred, as for the RGB-D check's motion).
RollingShutterFit CorrectPairsForRollingShutter(PairSet& pairs, const std::vector<bool>& use,
                                                const RollingShutterInput& in, const DynamicConfig& config);

// One undistorted position seen at raw row `raw_row`, turned to the middle-row
// camera of a frame turning at w (rad/s).
cv::Point2f ToMiddleRow(const cv::Point2f& un, double raw_row, const Eigen::Vector3d& w, const RollingShutterInput& in);

}  // namespace sgslam::dynamic
