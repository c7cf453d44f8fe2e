#include "sgslam/dynamic/undistort_table.h"

#include <cmath>

namespace sgslam::dynamic {

UndistortTable::UndistortTable(cv::Size image, Exact exact, int step)
    : exact_(std::move(exact)),
      step_(std::max(step, 1)),
      cols_((image.width - 1) / step_ + 2),  // one node beyond the last pixel
      rows_((image.height - 1) / step_ + 2) {
  grid_.reserve(static_cast<size_t>(cols_) * static_cast<size_t>(rows_));
  for (int y = 0; y < rows_; ++y) {
    for (int x = 0; x < cols_; ++x) grid_.emplace_back(static_cast<float>(x * step_), static_cast<float>(y * step_));
  }
  exact_(grid_);
}

void UndistortTable::Apply(std::vector<cv::Point2f>& points) const {
  std::vector<size_t> outside;
  const float inv = 1.0f / static_cast<float>(step_);
  for (size_t i = 0; i < points.size(); ++i) {
    cv::Point2f& p = points[i];
    const float fx = p.x * inv, fy = p.y * inv;
    if (!(fx >= 0 && fy >= 0 && fx < static_cast<float>(cols_ - 1) && fy < static_cast<float>(rows_ - 1))) {
      outside.push_back(i);  // also NaN
      continue;
    }
    const int x0 = static_cast<int>(fx), y0 = static_cast<int>(fy);
    const float ax = fx - static_cast<float>(x0), ay = fy - static_cast<float>(y0);
    const cv::Point2f* r0 = &grid_[static_cast<size_t>(y0) * static_cast<size_t>(cols_) + static_cast<size_t>(x0)];
    const cv::Point2f* r1 = r0 + cols_;
    p = (1 - ay) * ((1 - ax) * r0[0] + ax * r0[1]) + ay * ((1 - ax) * r1[0] + ax * r1[1]);
  }
  if (outside.empty()) return;
  std::vector<cv::Point2f> rest;
  for (size_t i : outside) rest.push_back(points[i]);
  exact_(rest);
  for (size_t k = 0; k < outside.size(); ++k) points[outside[k]] = rest[k];
}

}  // namespace sgslam::dynamic
