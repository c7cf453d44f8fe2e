// Per-pixel ray casting against quads: the exact depth and the visible surface of
// every pixel centre. Each quad only visits the screen rectangle its projection
// covers (the full image when a corner is behind the camera).
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "sgslam/synth/geometry.h"

namespace sgslam::synth {

// The synthetic camera: 640x480 pinhole, no distortion (fx = fy = 525).
struct Intrinsics {
  int width = 640, height = 480;  // px
  double fx = 525.0, fy = 525.0;  // px
  double cx = 319.5, cy = 239.5;  // px
  // Ray through pixel (u, v) with z = 1 in the camera frame.
  Eigen::Vector3d Ray(double u, double v) const { return {(u - cx) / fx, (v - cy) / fy, 1.0}; }
};

struct RayCastResult {
  std::vector<double> depth;  // m, camera z of the hit, row-major; +inf where nothing is hit
  cv::Mat surface;            // CV_32S, index into the quads, -1 where nothing is hit
};

// quads_c: the surfaces in the camera frame (x right, y down, z forward).
RayCastResult RayCast(const std::vector<Quad>& quads_c, const Intrinsics& K);

// A rolling shutter: row y is seen from its own camera, T_c_w_rows[y] (one per
// row, K.height of them); quads_w in the world frame. Depths are camera z of the
// row's camera.
RayCastResult RayCastRows(const std::vector<Quad>& quads_w, const std::vector<SE3>& T_c_w_rows, const Intrinsics& K);

}  // namespace sgslam::synth
