// The network backend of the detection thread: a Darknet Yolo-Fastest 1.1 model on
// OpenCV dnn, CPU only. The paper ran MobileNetV3-SSDLite on NCNN (Sec. III-B) and
// notes that other detectors fit "depending on the hardware"; Yolo-Fastest is the
// CPU detector NGD-SLAM uses, and its COCO classes cover the VOC ones the paper
// relies on (models/yolo-fastest-1.1-coco/README.md).
//
// Thread budget. cv::setNumThreads is process-wide: it sets how many threads every
// OpenCV parallel_for_ of the process may use, tracking's included. The programs
// (sgslam run, the ROS node) apply config.threads (default 1) once, before any
// thread starts, and a library sets no process-wide state: so inference runs on the detection
// thread alone and tracking's OpenCV calls (pyramids, blur, LK flow, RANSAC) run
// on the tracking thread alone: on a 2-core machine each thread gets one core and
// neither waits for the other's thread pool. With OpenCV's default (all cores),
// inference is no faster on two cores (bench/detector_bench.cpp) and, because
// OpenCV runs a parallel_for_ started while another one is active (in any
// thread) serially, tracking's calls would lose their parallelism anyway whenever
// the detector is busy, which in this design is most of each frame.
//
// Not thread-safe: one thread calls Detect() (the DetectionWorker's).
#pragma once

#include <string>
#include <vector>

#include "sgslam/detection/darknet_model.h"
#include "sgslam/detection/detector.h"
#include "sgslam/detection/yolo_decode.h"

namespace sgslam {

class DnnDetector final : public Detector {
 public:
  // Loads <model>.{cfg,weights} and coco.names from the folder ResolveModelDir finds
  // (model_dir, else $SGSLAM_MODEL_DIR, else the shipped models).
  // Throws InputError naming the folder or file at fault.
  explicit DnnDetector(const DetectorConfig& config);

  std::vector<Detection> Detect(const cv::Mat& bgr, Timestamp t) override;
  std::string Describe() const override;
  const std::vector<std::string>& class_names() const { return model_.class_names; }

 private:
  DetectorConfig config_;
  DarknetModel model_;
  YoloDecodeParams decode_;
  std::vector<std::string> output_names_;
  std::vector<cv::Mat> outputs_;  // reused between frames
};

}  // namespace sgslam
