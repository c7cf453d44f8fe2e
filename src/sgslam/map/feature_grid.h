// Buckets keypoints into a coarse grid over the undistorted image so that the
// keypoints near a predicted position are found without scanning them all.
#pragma once

#include <cstdint>
#include <vector>

#include <opencv2/core/types.hpp>

namespace sgslam {

// The undistorted image's bounding box: lens distortion moves the corners, so
// undistorted keypoints may fall outside [0, width) x [0, height).
struct ImageBounds {
  double min_x = 0, max_x = 0, min_y = 0, max_y = 0;
  bool Contains(double u, double v) const { return u >= min_x && u < max_x && v >= min_y && v < max_y; }
};

class FeatureGrid {
 public:
  static constexpr int kCols = 64;
  static constexpr int kRows = 48;

  FeatureGrid() = default;
  FeatureGrid(const std::vector<cv::KeyPoint>& keys_un, const ImageBounds& bounds);

  // Indices of keypoints (the same keys_un the grid was built from) within the
  // square of half side r around (u, v), with octave in [min_level, max_level]
  // (a negative bound means none).
  std::vector<std::size_t> InArea(const std::vector<cv::KeyPoint>& keys_un, double u, double v, double r,
                                  int min_level = -1, int max_level = -1) const;

 private:
  ImageBounds bounds_;
  double inv_cell_w_ = 0, inv_cell_h_ = 0;
  std::vector<std::vector<std::uint32_t>> cells_;  // row-major kRows x kCols
};

}  // namespace sgslam
