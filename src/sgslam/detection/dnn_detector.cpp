#include "sgslam/detection/dnn_detector.h"

#include <algorithm>
#include <cstdio>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

namespace sgslam {

DnnDetector::DnnDetector(const DetectorConfig& config) : config_(config) {
  decode_.score_threshold = static_cast<float>(config.score_threshold);
  decode_.person_score_threshold = static_cast<float>(config.person_score_threshold);
  const float floor = std::min(decode_.score_threshold, decode_.person_score_threshold);
  model_ = LoadDarknetModel(ResolveModelDir(config.model_dir), config.model, floor);
  output_names_ = model_.net.getUnconnectedOutLayersNames();
}

std::vector<Detection> DnnDetector::Detect(const cv::Mat& image, Timestamp /*t*/) {
  if (image.empty()) return {};
  cv::Mat bgr = image;
  if (image.type() == CV_8UC1) cv::cvtColor(image, bgr, cv::COLOR_GRAY2BGR);
  if (image.type() == CV_8UC4) cv::cvtColor(image, bgr, cv::COLOR_BGRA2BGR);
  CV_Assert(bgr.type() == CV_8UC3);
  // Darknet was trained on RGB scaled to [0, 1], stretched to the input square
  // (no crop, no letterbox). The SG-SLAM release fed BGR (reference notes).
  const cv::Mat blob = cv::dnn::blobFromImage(bgr, 1.0 / 255.0, cv::Size(config_.input_size, config_.input_size),
                                              cv::Scalar(), /*swapRB=*/true, /*crop=*/false);
  model_.net.setInput(blob);
  model_.net.forward(outputs_, output_names_);
  return DecodeYoloOutputs(outputs_, bgr.size(), model_.class_names, decode_);
}

std::string DnnDetector::Describe() const {
  char buf[200];
  std::snprintf(buf, sizeof buf, "; input %dx%d, score >= %.2f (person >= %.2f), NMS IoU %.2f, OpenCV threads %d",
                config_.input_size, config_.input_size, config_.score_threshold, config_.person_score_threshold,
                static_cast<double>(decode_.nms_threshold), cv::getNumThreads());
  return "OpenCV dnn " + model_.cfg.string() + buf;
}

}  // namespace sgslam
