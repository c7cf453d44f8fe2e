// Coloured point clouds for the semantic map: a voxel-grid filter (a voxel hash of
// our own: no PCL), the undistorted ray of every pixel, and the back-projection of
// a keyframe's depth image without its dynamic pixels (paper Sec. III-E).
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "sgslam/io/ply.h"
#include "sgslam/semantic/semantic_config.h"

namespace sgslam {

class Camera;

// px; with semantic.filters.depth_edges, pixels within this Chebyshev distance of a
// depth step (cloud.cpp: 0.05 m + 0.02 / m * z^2) stay out of the cloud and the
// OctoMap: at a mover's outline mask and depth disagree by a pixel or two, and the
// depth there mixes two surfaces (docs/results-archive.md, "Three export filters").
inline constexpr int kDepthEdgeRadius = 2;

struct ColoredPoint {
  Eigen::Vector3f p;  // m
  Rgb rgb{0, 0, 0};
};

// One point per occupied voxel of side `voxel`: the mean position and colour of the
// points in it, in the order the voxels were first met (deterministic).
std::vector<ColoredPoint> VoxelDownsample(const std::vector<ColoredPoint>& in, double voxel);

// The normalised, undistorted ray (x/z, y/z) of every pixel of a camera's images,
// computed once: back-projection then costs a multiply per pixel.
class PixelRays {
 public:
  explicit PixelRays(const Camera& camera);
  const cv::Vec2f& at(int u, int v) const { return rays_.at<cv::Vec2f>(v, u); }
  cv::Size size() const { return rays_.size(); }

 private:
  cv::Mat rays_;  // CV_32FC2
};

// Every `stride`-th pixel with a depth in [depth_min, depth_max] and mask == 0, in
// the camera frame, with its colour (bgr may be 1 or 3 channels); not downsampled.
// With config.filters.depth_edges, not the pixels within kDepthEdgeRadius of a depth step.
std::vector<ColoredPoint> BackProject(const cv::Mat& bgr, const cv::Mat& depth_raw, double depth_factor,
                                      const cv::Mat& mask, const PixelRays& rays, int stride,
                                      const SemanticConfig& config);

}  // namespace sgslam
