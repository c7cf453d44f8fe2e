#include "sgslam/map/feature_grid.h"

#include <algorithm>
#include <cmath>

namespace sgslam {

FeatureGrid::FeatureGrid(const std::vector<cv::KeyPoint>& keys_un, const ImageBounds& bounds)
    : bounds_(bounds),
      inv_cell_w_(kCols / (bounds.max_x - bounds.min_x)),
      inv_cell_h_(kRows / (bounds.max_y - bounds.min_y)),
      cells_(kCols * kRows) {
  for (std::size_t i = 0; i < keys_un.size(); ++i) {
    const int cx = static_cast<int>(std::floor((keys_un[i].pt.x - bounds.min_x) * inv_cell_w_));
    const int cy = static_cast<int>(std::floor((keys_un[i].pt.y - bounds.min_y) * inv_cell_h_));
    if (cx < 0 || cx >= kCols || cy < 0 || cy >= kRows) continue;  // outside the undistorted image
    cells_[cy * kCols + cx].push_back(static_cast<std::uint32_t>(i));
  }
}

std::vector<std::size_t> FeatureGrid::InArea(const std::vector<cv::KeyPoint>& keys_un, double u, double v, double r,
                                             int min_level, int max_level) const {
  std::vector<std::size_t> out;
  if (cells_.empty()) return out;
  const int x0 = std::max(0, static_cast<int>(std::floor((u - r - bounds_.min_x) * inv_cell_w_)));
  const int x1 = std::min(kCols - 1, static_cast<int>(std::floor((u + r - bounds_.min_x) * inv_cell_w_)));
  const int y0 = std::max(0, static_cast<int>(std::floor((v - r - bounds_.min_y) * inv_cell_h_)));
  const int y1 = std::min(kRows - 1, static_cast<int>(std::floor((v + r - bounds_.min_y) * inv_cell_h_)));
  if (x0 > x1 || y0 > y1) return out;
  const bool check_levels = min_level > 0 || max_level >= 0;
  for (int cy = y0; cy <= y1; ++cy) {
    for (int cx = x0; cx <= x1; ++cx) {
      for (std::uint32_t i : cells_[cy * kCols + cx]) {
        const cv::KeyPoint& k = keys_un[i];
        if (check_levels) {
          if (k.octave < min_level) continue;
          if (max_level >= 0 && k.octave > max_level) continue;
        }
        if (std::abs(k.pt.x - u) < r && std::abs(k.pt.y - v) < r) out.push_back(i);
      }
    }
  }
  return out;
}

}  // namespace sgslam
