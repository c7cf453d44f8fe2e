// Which pixels of a keyframe belong to moving objects and stay out of the static
// map (paper Sec. III-E: point clouds and the OctoMap leave dynamic objects out):
//  - every box of a dynamic class (ClassTable::is_dynamic, e.g. person), grown by
//    box_margin of its size on each side since detector boxes are loose;
//  - around each keypoint that tracking rejected as dynamic outside those boxes
//    (motion the detector missed, e.g. an unknown moving box), the pixels within
//    motion_radius whose depth lies within a band of the keypoint's:
//    the moving surface near the keypoint, not the background behind it;
//  - every smooth depth segment (of at most half the image)
//    where enough keypoints, and most of its keypoints, were rejected: the whole
//    surface of an object that moves as one. Keypoints kept without a geometric
//    test (unjudged, one flag per key or empty) do not count there
//    (motion_segment_skip_unjudged).
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "sgslam/detection/detection.h"
#include "sgslam/detection/detector_config.h"
#include "sgslam/semantic/semantic_config.h"

namespace sgslam {

// m; of a dynamic box, the pixels this close to the depth of its middle are the
// mover itself, for the seen-moving filter (semantic.seen_moving_ratio).
inline constexpr double kSeenMovingBand = 0.2;

// CV_8UC1, 255 = dynamic. keys: raw keypoint positions; rejected: one flag per key (or empty).
// surface (optional): the same mask but with, of each dynamic box, only the pixels
// within kSeenMovingBand of the depth of its middle (BoxMedianDepth): where the
// mover itself was, not the background its box frames.
cv::Mat DynamicPixelMask(const cv::Mat& depth_raw, double depth_factor, const std::vector<Detection>& detections,
                         const ClassTable& classes, const std::vector<cv::KeyPoint>& keys,
                         const std::vector<std::uint8_t>& rejected, const SemanticConfig& config,
                         const std::vector<std::uint8_t>& unjudged = {}, cv::Mat* surface = nullptr);

}  // namespace sgslam
