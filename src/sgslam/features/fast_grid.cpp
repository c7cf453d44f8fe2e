#include "sgslam/features/fast_grid.h"

#include <algorithm>
#include <opencv2/features2d.hpp>

namespace sgslam::features {

namespace {
constexpr int kFastRadius = 3;  // FAST-9's circle; it reports no corner closer to a ROI border
}

cv::Rect DetectionRegion(cv::Size level_size) {
  const int border = kEdgeThreshold - kFastRadius;
  const int w = level_size.width - 2 * border, h = level_size.height - 2 * border;
  if (w <= 2 * kFastRadius || h <= 2 * kFastRadius) return {};
  return {border, border, w, h};
}

std::vector<cv::KeyPoint> DetectFastInCells(const cv::Mat& image, const FastCellParams& params) {
  std::vector<cv::KeyPoint> out;
  const cv::Rect region = DetectionRegion(image.size());
  if (region.empty()) return out;

  const int cols = std::max(1, region.width / params.cell_size);
  const int rows = std::max(1, region.height / params.cell_size);
  const int cell_w = (region.width + cols - 1) / cols;
  const int cell_h = (region.height + rows - 1) / rows;

  std::vector<cv::KeyPoint> cell_kps;
  for (int r = 0; r < rows; ++r) {
    const int y0 = region.y + r * cell_h;
    if (y0 >= region.br().y - 2 * kFastRadius) continue;
    // Cells overlap by 2 * kFastRadius so their interiors (where FAST can fire)
    // tile the region without gaps.
    const int y1 = std::min(y0 + cell_h + 2 * kFastRadius, region.br().y);
    for (int c = 0; c < cols; ++c) {
      const int x0 = region.x + c * cell_w;
      if (x0 >= region.br().x - 2 * kFastRadius) continue;
      const int x1 = std::min(x0 + cell_w + 2 * kFastRadius, region.br().x);
      const cv::Mat cell = image(cv::Range(y0, y1), cv::Range(x0, x1));
      cv::FAST(cell, cell_kps, params.threshold, true);
      if (cell_kps.empty()) cv::FAST(cell, cell_kps, params.min_threshold, true);
      for (cv::KeyPoint& kp : cell_kps) {
        kp.pt.x += static_cast<float>(x0);
        kp.pt.y += static_cast<float>(y0);
        out.push_back(kp);
      }
    }
  }
  return out;
}

}  // namespace sgslam::features
