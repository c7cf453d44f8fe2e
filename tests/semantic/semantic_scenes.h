// Small fixed scenes shared by the semantic tests: an undistorted 640x480 camera
// and a depth image of a face standing before a wall.
#pragma once

#include <opencv2/core.hpp>

#include "sgslam/config/config.h"

namespace sgslam::test {

// fx = fy = 500 px, principal point at the image centre, no distortion.
inline CameraConfig PinholeCamera() {
  CameraConfig c;
  c.fx = c.fy = 500;
  c.cx = 319.5;
  c.cy = 239.5;
  c.k1 = c.k2 = c.p1 = c.p2 = c.k3 = 0;
  return c;
}

// Raw depth (5000 per metre): a wall at 4 m with a face at 2 m over pixels
// [200, 300) x [150, 330).
inline cv::Mat FaceBeforeWall() {
  cv::Mat d(480, 640, CV_16UC1, cv::Scalar(4 * 5000));
  d(cv::Rect(200, 150, 100, 180)).setTo(2 * 5000);
  return d;
}

}  // namespace sgslam::test
