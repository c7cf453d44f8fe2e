// FAST detection in cells (ORB-SLAM2's design): one global threshold finds
// nothing in low-contrast regions and thousands on textured ones, so each cell
// of ~cell_size px first tries the normal threshold and, only if that finds
// nothing, a lower one. The quadtree (quadtree.h) then thins the candidates.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

namespace sgslam::features {

// Keypoints must stay this far from a level's border so that the rotated
// 31x31 BRIEF patch (corners up to ~19 px from the centre) stays inside it.
inline constexpr int kEdgeThreshold = 19;
inline constexpr int kPatchSize = 31;
inline constexpr int kHalfPatchSize = kPatchSize / 2;

// FAST runs on [kEdgeThreshold-3, size-kEdgeThreshold+3): its 3 px circle
// radius puts every corner it reports at least kEdgeThreshold px inside.
// Empty when the level is too small.
cv::Rect DetectionRegion(cv::Size level_size);

struct FastCellParams {
  int cell_size = 35;     // px
  int threshold = 20;     // intensity, tried first
  int min_threshold = 7;  // intensity, fallback when a cell finds nothing
};

// Non-max-suppressed FAST-9 corners of `image` (8-bit) in its DetectionRegion,
// in the image's pixel coordinates, response = FAST score. Deterministic order.
std::vector<cv::KeyPoint> DetectFastInCells(const cv::Mat& image, const FastCellParams& params);

}  // namespace sgslam::features
