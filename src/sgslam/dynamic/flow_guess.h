// Where each current keypoint was in the previous image if it is static, from the
// tracker's constant-velocity motion and the current depth: the starting point of
// the backward LK flow when dynamic.lk_predict is on. Without it LK starts at the
// keypoint's own position and must find the whole image motion through its
// pyramid (tens of px a frame in fr1's fast turns); with it one level above the
// image is enough, which saves about a quarter of the rejection's time. A mover
// still gets its own flow: LK converges from the static prediction to where the
// mover's patch really was, within the reduced pyramid's reach. See
// dynamic_config.h for what it costs in accuracy.
// Thread safety: a free function on const inputs.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "sgslam/common/se3.h"
#include "sgslam/dynamic/depth_check.h"

namespace sgslam::dynamic {

struct FlowPrediction {
  cv::Mat cur_depth;           // CV_16U raw (depth_factor) or CV_32F metres; 0 = no measurement
  double depth_factor = 5000;  // raw units per metre, CV_16U only
  Pinhole K;
  SE3 T_cur_prev;  // predicted motion, previous camera -> current camera
};

// cur_raw: keypoints as detected; cur_un: the same undistorted (= cur_raw without
// distortion). Returns raw positions in the previous image: the predicted
// undistorted displacement added to the raw keypoint (the distortion changes
// little over a frame's displacement, and LK refines the rest). A keypoint
// without depth is lifted at the median depth of those with one (2 m when none
// has): under rotation, which dominates the image motion, depth hardly matters.
std::vector<cv::Point2f> PredictPrevious(const std::vector<cv::Point2f>& cur_raw,
                                         const std::vector<cv::Point2f>& cur_un, const FlowPrediction& prediction,
                                         double depth_min, double depth_max);

}  // namespace sgslam::dynamic
