// Algorithm 1 line 5-6: which dynamic-object region a keypoint lies in, and its
// prior dynamic weight w (paper Sec. III-D: 1..5, 1 = static class).
#pragma once

#include <functional>
#include <opencv2/core/mat.hpp>
#include <opencv2/core/types.hpp>
#include <string>
#include <vector>

#include "sgslam/detection/detection.h"

namespace sgslam::dynamic {

// Prior weight w of a class name, 1 (static) .. 5; the class table provides it.
using WeightFn = std::function<double(const std::string& class_name)>;

// Per keypoint, the largest w among the detection boxes containing it (overlapping
// boxes: the most dynamic class counts); 1 outside every box of weight > 1.
// An empty weight function treats every detection as static.
std::vector<double> KeypointWeights(const std::vector<cv::KeyPoint>& keys, const std::vector<Detection>& detections,
                                    const WeightFn& weight);

// The same with depth: a detector box is a rectangle around an outline, and the
// background it frames is static, yet Algorithm 1 line 6 would hold it to d < eps / w.
// The object's depth is taken from the box's centre (the `object_percentile` of
// the depths sampled on a grid over its middle half in x and 10-90 % in y: the
// nearer part, which the object fills in front of what lies behind it); a keypoint
// measured more than `band` metres behind it is background and keeps w = 1 for that
// box. Keypoints without depth, and boxes with too few depth samples, keep w.
// depth: the frame's depth in metres (CV_32F) or raw CV_16U with depth_factor,
// sampled at the keypoints' (raw) pixels. band <= 0: plain KeypointWeights.
std::vector<double> KeypointWeightsWithDepth(const std::vector<cv::KeyPoint>& keys,
                                             const std::vector<Detection>& detections, const WeightFn& weight,
                                             const cv::Mat& depth, double depth_factor, double band,
                                             double object_percentile = 0.25);

// The object depth of a box as above (m), or 0 with fewer than 8 valid samples.
double BoxObjectDepth(const cv::Rect2f& box, const cv::Mat& depth, double depth_factor, double percentile);

}  // namespace sgslam::dynamic
