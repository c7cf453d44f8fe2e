// Post-processing of the outputs of OpenCV's Darknet [yolo] layers into boxes.
// In OpenCV 4.6 each output row is (cx, cy, w, h, objectness, 80 class scores) with
// the box relative to the network input and each class score already multiplied by
// the objectness (and zeroed at or below the layer's thresh), so the class column
// is the detection score itself.
#pragma once

#include <opencv2/core/mat.hpp>
#include <string>
#include <vector>

#include "sgslam/detection/detection.h"

namespace sgslam {

struct YoloDecodeParams {
  float score_threshold = 0.4f;  // classes other than person
  float person_score_threshold = 0.15f;
  float nms_threshold = 0.45f;  // IoU, per class
};

// image: size of the image the blob was made from without crop or letterbox, so
// relative coordinates scale by its width and height. Every class of a row above
// its threshold gives a candidate (Darknet does the same); NMS runs per class;
// boxes are clipped to the image. Sorted by class id, then by decreasing score.
std::vector<Detection> DecodeYoloOutputs(const std::vector<cv::Mat>& outputs, cv::Size image,
                                         const std::vector<std::string>& class_names, const YoloDecodeParams& params);

}  // namespace sgslam
