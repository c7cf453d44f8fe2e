// One depth pixel in metres, from either encoding the dynamic stage sees: raw
// CV_16U (divided by depth_factor, TUM: 5000 per metre) or CV_32F metres. 0 (or
// non-finite for float images) means no measurement. The caller checks bounds.
#pragma once

#include <cstdint>
#include <opencv2/core/mat.hpp>

namespace sgslam::dynamic {

inline double DepthAt(const cv::Mat& depth, int x, int y, double depth_factor) {
  if (depth.type() == CV_16U) return depth.at<std::uint16_t>(y, x) / depth_factor;
  return depth.at<float>(y, x);
}

}  // namespace sgslam::dynamic
