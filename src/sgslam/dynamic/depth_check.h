// A second, independent motion test from RGB-D (the paper's named blind spot: a
// point moving along its epipolar line passes eq. 4). The previous point is lifted
// with the previous depth, moved by the camera motion T_cur_prev and compared with
// what the current frame measures: its depth at the current keypoint, and the
// keypoint's position. A point is flagged as moved when
//   |z_pred - z_meas| > depth_tolerance + depth_tolerance_quadratic * z^2
// (Kinect depth noise grows with z^2, Khoshelham & Elberink 2012; the smallest
// error over the previous depths of a (2 depth_check_window + 1)^2 window and the
// current 3x3), or when the reprojection error (the smallest over that previous
// window) exceeds reprojection_tolerance px, or reprojection_median_factor times
// the frame's median reprojection error when that is larger (under fast rotation a
// rolling shutter and an imprecise motion move every static point off together, a
// mover stands out of that level). The second term is what catches the degenerate
// preset: a walker moving sideways parallel to the camera keeps its depth and
// stays on its epipolar line, but not where a static point would reproject.
//
// Coordinates: depth images are sampled at the raw keypoint/flow positions (TUM
// depth is registered to the colour image). The geometry uses undistorted pixels:
// pass `undistort` when the images are distorted; without it the positions are
// taken as undistorted. T_cur_prev is the PnP motion of the flow pairs (motion.h);
// its error adds to the tolerances, see the tests for a measure.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <limits>
#include <opencv2/core.hpp>
#include <vector>

#include "sgslam/common/se3.h"
#include "sgslam/dynamic/dynamic_config.h"
#include "sgslam/geometry/pinhole.h"

namespace sgslam::dynamic {

using geometry::Pinhole;

using UndistortFn = std::function<Eigen::Vector2d(const Eigen::Vector2d&)>;  // raw px -> undistorted px

struct DepthCheckInput {
  cv::Mat prev_depth;          // CV_16U raw (see depth_factor) or CV_32F metres; 0 = no measurement
  cv::Mat cur_depth;           // same encoding, same size as the grey images
  double depth_factor = 5000;  // raw units per metre, CV_16U only
  Pinhole K;
  SE3 T_cur_prev;         // maps previous-camera points into the current camera
  UndistortFn undistort;  // empty: positions are already undistorted
  // The reprojection tolerance may rise to reprojection_median_factor times the
  // frame's median residual (JudgePairs: in sg only, where the boxes keep most
  // movers out of that median).
  bool median_level = true;
};

struct DepthResidual {
  bool valid = false;             // both depths measured and in range
  bool moved = false;             // beyond the tolerances
  double depth_error = 0;         // m, |z_pred - z_meas|
  double reprojection_error = 0;  // px
  double depth_tolerance = 0;         // m, the depth error allowed for this point
  // px, the reprojection error allowed in this frame; infinity when the reprojection
  // test is off (reprojection_tolerance 0), so that nothing reads it as "none allowed"
  double reprojection_tolerance = std::numeric_limits<double>::infinity();
};

// One result per pair; pairs with use[i] false are skipped (valid false).
std::vector<DepthResidual> CheckDepth(const std::vector<cv::Point2f>& prev, const std::vector<cv::Point2f>& cur,
                                      const std::vector<bool>& use, const DepthCheckInput& input,
                                      const DynamicConfig& config);

// The same with the undistorted positions given (input.undistort is not used):
// depth is sampled at prev_raw/cur_raw, the geometry uses prev_un/cur_un.
std::vector<DepthResidual> CheckDepth(const std::vector<cv::Point2f>& prev_raw, const std::vector<cv::Point2f>& cur_raw,
                                      const std::vector<cv::Point2f>& prev_un, const std::vector<cv::Point2f>& cur_un,
                                      const std::vector<bool>& use, const DepthCheckInput& input,
                                      const DynamicConfig& config);

}  // namespace sgslam::dynamic
