#include "sgslam/detection/file_detector.h"

#include <cstdlib>

#include "sgslam/detection/detections_file.h"

namespace sgslam {

FileDetector::FileDetector(const std::filesystem::path& file) : file_(file), frames_(ReadDetectionsFile(file)) {}

std::vector<Detection> FileDetector::Detect(const cv::Mat& /*bgr*/, Timestamp t) {
  // The first listed frame at or after t - tolerance; a nearer one may follow it
  // only if two listed frames lie within the tolerance window.
  auto best = frames_.end();
  for (auto it = frames_.lower_bound(t - kTolerance); it != frames_.end() && it->first <= t + kTolerance; ++it) {
    if (best == frames_.end() || std::abs(it->first - t) < std::abs(best->first - t)) best = it;
  }
  if (best == frames_.end()) return {};
  return best->second;
}

std::string FileDetector::Describe() const {
  return "detections file " + file_.string() + " (" + std::to_string(frames_.size()) + " frames with detections)";
}

}  // namespace sgslam
