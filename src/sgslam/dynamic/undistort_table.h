// Raw -> undistorted pixel lookup for the flow pairs. Camera::Undistort iterates
// to convergence, too slow for every pair of every frame; the map is smooth, so it
// is sampled once on a grid of `step` px and interpolated bilinearly (the error
// bound is in tests/dynamic/undistort_table_test.cpp). Points outside the grid go
// to the exact function.
// Thread safety: const after construction.
#pragma once

#include <functional>
#include <opencv2/core.hpp>
#include <vector>

namespace sgslam::dynamic {

class UndistortTable {
 public:
  using Exact = std::function<void(std::vector<cv::Point2f>&)>;  // raw px -> undistorted px, in place

  UndistortTable(cv::Size image, Exact exact, int step = 2);

  void Apply(std::vector<cv::Point2f>& points) const;

 private:
  Exact exact_;
  int step_, cols_, rows_;        // grid nodes at (x * step, y * step), x < cols, y < rows
  std::vector<cv::Point2f> grid_;  // undistorted node positions, row-major
};

}  // namespace sgslam::dynamic
