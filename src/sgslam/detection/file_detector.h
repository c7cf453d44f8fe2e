// Replays the detections of a detections file (io/detections_file.h), e.g. the
// ground truth that `sgslam synth` writes, instead of running a network: tracking
// and mapping can then be tested with perfect or recorded semantics.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "sgslam/detection/detector.h"

namespace sgslam {

class FileDetector final : public Detector {
 public:
  // Frames match when their timestamps differ by at most this; TUM timestamps have
  // 6 decimals, frames are >= 10 ms apart.
  static constexpr Timestamp kTolerance = 1'000'000;  // ns (1 ms)

  // Reads the whole file. Throws InputError naming a missing file, ParseError for a
  // malformed line.
  explicit FileDetector(const std::filesystem::path& file);

  // The detections of the frame nearest to t within kTolerance; none for frames
  // the file does not list (a frame without detections leaves no line). The image
  // is not looked at.
  std::vector<Detection> Detect(const cv::Mat& bgr, Timestamp t) override;
  std::string Describe() const override;

 private:
  std::filesystem::path file_;
  std::map<Timestamp, std::vector<Detection>> frames_;
};

}  // namespace sgslam
