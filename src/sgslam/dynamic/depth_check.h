// A second, independent motion test from RGB-D (refinement R5 of refinements.h; the
// paper's named blind spot: a point moving along its epipolar line passes eq. 4).
// The previous point is lifted with the previous depth, moved by the camera motion
// T_cur_prev and compared with what the current frame measures: its depth at the
// current keypoint, and the keypoint's position. A point is flagged as moved when
//   |z_pred - z_meas| > kDepthTolerance + kDepthToleranceQuadratic * z^2
// (Kinect depth noise grows with z^2, Khoshelham & Elberink 2012; the smallest
// error over the previous depths of a (2 window + 1)^2 window and the current 3x3),
// or when the reprojection error (the smallest over that previous window) exceeds
// reprojection_tolerance px, or reprojection_median_factor times the frame's median
// reprojection error when that is larger (under fast rotation a rolling shutter and
// an imprecise motion move every static point off together, a mover stands out of
// that level). The second term is what catches the degenerate preset: a walker
// moving sideways parallel to the camera keeps its depth and stays on its epipolar
// line, but not where a static point would reproject.
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
#include "sgslam/geometry/pinhole.h"

namespace sgslam::dynamic {

using geometry::Pinhole;

// R5's constants. Not measured on their own unless named (docs/algorithm1.md, R5).
// m, the depth range the check (and its PnP, motion.h) uses: a Kinect-like sensor's
// depth outside it is missing or too noisy to compare.
constexpr double kDepthMin = 0.2;
constexpr double kDepthMax = 6.0;
constexpr double kDepthTolerance = 0.03;            // m, depth error allowed at any range (sensor noise)
constexpr double kDepthToleranceQuadratic = 0.006;  // 1/m, plus this times depth^2 (Kinect-like noise grows so)
// px, reprojection error allowed at least; the same 3 px as eps_std's default.
constexpr double kReprojectionTolerance = 3.0;
// sg: the reprojection tolerance is at least this times the frame's median residual:
// fast turns move every static point off together (measured on fr1_rpy and dyn_dev).
constexpr double kReprojectionMedianFactor = 3.0;
// px, half-size of the window of previous depths a point is lifted with: a static
// point next to a depth edge lifted with the other surface's depth lands pixels off.
constexpr int kDepthCheckWindow = 1;
// A check that flags more than this share of the pairs it tested is ignored: the
// scene is assumed mostly static, so its motion is wrong (a PnP on a large mover,
// dyn_dev frame 73).
constexpr double kDepthMaxShare = 0.5;
// sg: a keypoint in a dynamic box whose check passes within this share of both
// tolerances is judged at w = 1: direct evidence outweighs the box's prior
// (measured on dyn_dev).
constexpr double kConfirmStatic = 0.33;

// What the tests vary; the pipeline runs at the defaults. CheckDepth reads the
// first three; max_share and confirm_static are for CheckPairDepths (refinements.h).
struct DepthCheckParams {
  int window = kDepthCheckWindow;                                   // px; 0: the pixel itself
  double reprojection_tolerance = kReprojectionTolerance;          // px; 0: depth only
  double reprojection_median_factor = kReprojectionMedianFactor;  // 0: the fixed tolerance
  double max_share = kDepthMaxShare;                               // share of the checked pairs
  double confirm_static = kConfirmStatic;                          // share of the tolerances; 0: off
};

using UndistortFn = std::function<Eigen::Vector2d(const Eigen::Vector2d&)>;  // raw px -> undistorted px

struct DepthCheckInput {
  cv::Mat prev_depth;          // CV_16U raw (see depth_factor) or CV_32F metres; 0 = no measurement
  cv::Mat cur_depth;           // same encoding, same size as the grey images
  double depth_factor = 5000;  // raw units per metre, CV_16U only
  Pinhole K;
  SE3 T_cur_prev;         // maps previous-camera points into the current camera
  UndistortFn undistort;  // empty: positions are already undistorted
  // The reprojection tolerance may rise to DepthCheckParams::reprojection_median_factor
  // times the frame's median residual (JudgePairs: in sg only, where the boxes keep most
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
  // test is off (DepthCheckParams::reprojection_tolerance 0), so that nothing reads it
  // as "none allowed"
  double reprojection_tolerance = std::numeric_limits<double>::infinity();
};

// One result per pair; pairs with use[i] false are skipped (valid false).
std::vector<DepthResidual> CheckDepth(const std::vector<cv::Point2f>& prev, const std::vector<cv::Point2f>& cur,
                                      const std::vector<bool>& use, const DepthCheckInput& input,
                                      const DepthCheckParams& params = {});

// The same with the undistorted positions given (input.undistort is not used):
// depth is sampled at prev_raw/cur_raw, the geometry uses prev_un/cur_un.
std::vector<DepthResidual> CheckDepth(const std::vector<cv::Point2f>& prev_raw, const std::vector<cv::Point2f>& cur_raw,
                                      const std::vector<cv::Point2f>& prev_un, const std::vector<cv::Point2f>& cur_un,
                                      const std::vector<bool>& use, const DepthCheckInput& input,
                                      const DepthCheckParams& params = {});

}  // namespace sgslam::dynamic
