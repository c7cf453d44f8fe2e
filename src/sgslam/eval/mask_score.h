// How well dynamic feature rejection matches ground truth: per frame, each
// keypoint is "moving" when the ground-truth dynamic mask is set at its (raw)
// position, and counted as rejected or kept. Sequences from `sgslam synth` and the
// dyn_dev sequence carry such masks (`mask.txt` + `mask/*.png`, 255 = moving).
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "sgslam/common/time.h"

namespace sgslam::eval {

struct MaskScore {
  std::uint64_t frames = 0;            // frames scored (with a mask)
  std::uint64_t moving = 0;            // keypoints on moving pixels
  std::uint64_t moving_rejected = 0;   // ... of them rejected (true positives)
  std::uint64_t static_points = 0;     // keypoints on static pixels
  std::uint64_t static_rejected = 0;   // ... of them rejected (false positives)
  // Static keypoints within kOutlinePx of a moving pixel, and of them rejected. A
  // corner there is mostly made by the mover's silhouette against the background
  // and moves with it (an occlusion corner, no fixed 3-D point), so the rejection
  // often takes it for moving. Reported apart so that the static loss can be read
  // both ways.
  std::uint64_t static_near = 0;
  std::uint64_t static_near_rejected = 0;
  static constexpr double kOutlinePx = 8.0;

  void Add(const MaskScore& o);
  double recall() const { return moving ? double(moving_rejected) / double(moving) : 0.0; }
  double static_loss() const { return static_points ? double(static_rejected) / double(static_points) : 0.0; }
  // The static loss of the keypoints at least kOutlinePx from every mover.
  double static_loss_away() const {
    const auto n = static_points - static_near;
    return n ? double(static_rejected - static_near_rejected) / double(n) : 0.0;
  }
  double precision() const {
    const auto rejected = moving_rejected + static_rejected;
    return rejected ? double(moving_rejected) / double(rejected) : 0.0;
  }
};

// Scores one frame: mask is CV_8UC1 (non-zero = moving), points in its pixels.
MaskScore ScoreKeypoints(const cv::Mat& mask, const std::vector<cv::Point2f>& points,
                         const std::vector<std::uint8_t>& rejected);

// The masks of a sequence, looked up by the RGB timestamp they were made for.
class MaskIndex {
 public:
  // Reads <dir>/mask.txt; an absent file gives an empty index (no scoring).
  // Throws InputError / ParseError for a malformed list, or one that is not a
  // regular file (a FIFO, a folder).
  explicit MaskIndex(const std::filesystem::path& dir);
  bool empty() const { return files_.empty(); }
  // The mask of the frame at t (within 1 ms), or nullopt. Throws InputError
  // naming the file when a listed mask cannot be read, is not a regular file, or
  // is larger (file or header) than any frame's mask.
  std::optional<cv::Mat> Load(Timestamp t) const;

 private:
  std::filesystem::path dir_;
  std::map<Timestamp, std::filesystem::path> files_;
};

}  // namespace sgslam::eval
