// Which pixels of a keyframe belong to moving objects and stay out of the static
// map (paper Sec. III-E: point clouds and the OctoMap leave dynamic objects out):
//  - every box of a dynamic class (ClassTable::is_dynamic, e.g. person), grown by
//    kBoxMargin of its size on each side since detector boxes are loose;
//  - around each keypoint that tracking rejected as dynamic outside those boxes
//    (motion the detector missed, e.g. an unknown moving box), the pixels within
//    kMotionRadius whose depth lies within a band of the keypoint's:
//    the moving surface near the keypoint, not the background behind it;
//  - with semantic.filters.motion_segments, every smooth depth segment (of at most
//    half the image) where enough keypoints, and most of its keypoints, were
//    rejected: the whole surface of an object that moves as one. Keypoints kept
//    without a geometric test (unjudged, one flag per key or empty) do not count
//    there (kSegmentSkipUnjudged).
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "sgslam/detection/detection.h"
#include "sgslam/detection/detector_config.h"

namespace sgslam {

// m; of a dynamic box, the pixels this close to the depth of its middle are the
// mover itself, for the seen-moving filter (semantic.filters.seen_moving): counting
// whole boxes took the background behind people with them.
inline constexpr double kSeenMovingBand = 0.2;
// Share of a dynamic box's width (height) added on each side before masking:
// detector boxes are loose and cut off hands, feet and hair.
inline constexpr double kBoxMargin = 0.05;
// px; around a rejected keypoint outside the dynamic boxes, the pixels this close
// (and near its depth) are masked: the moving surface the keypoint lies on.
inline constexpr int kMotionRadius = 25;
// Keypoints kept without a geometric test (no flow pair: a walker entering at the
// image edge, blur) count neither way in a moving segment's share: they outvoted
// the rejected ones on walkers entering the view (dyn_dev: 0.46 % of the cloud on
// movers without this rule, 0.39 % with it).
inline constexpr bool kSegmentSkipUnjudged = true;

// The mask's parameters: the pipeline passes the constants (and the
// motion_segments switch); tests vary them to isolate one rule.
struct DynamicMaskOptions {
  double box_margin = kBoxMargin;              // share of the box size, on each side
  int motion_radius = kMotionRadius;           // px; 0: no masking around rejected keypoints
  bool motion_segments = true;                 // semantic.filters.motion_segments
  bool skip_unjudged = kSegmentSkipUnjudged;   // unjudged keypoints do not vote in a segment
};

// CV_8UC1, 255 = dynamic. keys: raw keypoint positions; rejected: one flag per key (or empty).
// surface (optional): the same mask but with, of each dynamic box, only the pixels
// within kSeenMovingBand of the depth of its middle (BoxMedianDepth): where the
// mover itself was, not the background its box frames.
cv::Mat DynamicPixelMask(const cv::Mat& depth_raw, double depth_factor, const std::vector<Detection>& detections,
                         const ClassTable& classes, const std::vector<cv::KeyPoint>& keys,
                         const std::vector<std::uint8_t>& rejected, const DynamicMaskOptions& options,
                         const std::vector<std::uint8_t>& unjudged = {}, cv::Mat* surface = nullptr);

}  // namespace sgslam
