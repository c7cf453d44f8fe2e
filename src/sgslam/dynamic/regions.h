// Algorithm 1 line 5-6: which dynamic-object region a keypoint lies in, and its
// prior dynamic weight w (paper Sec. III-D: 1..5, 1 = static class).
#pragma once

#include <functional>
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

}  // namespace sgslam::dynamic
