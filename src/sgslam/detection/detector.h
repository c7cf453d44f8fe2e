// The detector interface of the object detection thread (paper Sec. III-B): one
// RGB frame in, 2-D boxes with COCO classes out. Backends: an OpenCV dnn network
// (dnn_detector.h) or the replay of a detections file (file_detector.h). Detect()
// is called by one thread at a time (DetectionWorker); it may throw on a broken
// backend, and the worker hands the exception to tracking.
#pragma once

#include <filesystem>
#include <memory>
#include <opencv2/core/mat.hpp>
#include <string>
#include <vector>

#include "sgslam/common/time.h"
#include "sgslam/detection/detection.h"
#include "sgslam/detection/detector_config.h"

namespace sgslam {

class Detector {
 public:
  virtual ~Detector() = default;
  // bgr: 8-bit BGR image (gray and BGRA are converted); boxes in its pixels.
  virtual std::vector<Detection> Detect(const cv::Mat& bgr, Timestamp t) = 0;
  // One line for the start-up log: backend, model or file, thresholds.
  virtual std::string Describe() const = 0;
};

// Builds the backend of config.backend; nullptr for "none". dataset_dir locates the
// default detections file of the file backend. Throws InputError naming the folder
// or file that is missing or unreadable, ConfigError for an unknown backend.
std::unique_ptr<Detector> MakeDetector(const DetectorConfig& config, const std::filesystem::path& dataset_dir);

}  // namespace sgslam
