// ORB extractor after ORB-SLAM2 (Mur-Artal & Tardos, 2017) and ORB (Rublee et
// al., 2011): a scale pyramid, FAST per cell with a fallback threshold, a
// quadtree per level for an even spread, intensity-centroid orientation and
// OpenCV's rotated BRIEF. Per level: pyramid.h, fast_grid.h, quadtree.h,
// orientation.h, descriptor.h.
//
// Threading: not thread-safe (but see set_threads). Extract() reuses the pyramid buffers and the
// accessors return references into them, so use one instance per thread
// (e.g. one for tracking). The next Extract() overwrites the pyramid images in
// place, so a caller that keeps pyramid() (say, for LK flow on the previous
// frame) must clone() the levels, not just copy the cv::Mat headers.
#pragma once

#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>
#include <vector>

#include "sgslam/features/orb_config.h"
#include "sgslam/features/fast_grid.h"
#include "sgslam/features/orientation.h"
#include "sgslam/features/pyramid.h"

namespace sgslam::features {

class OrbExtractor {
 public:
  // Throws ConfigError when `config` fails OrbConfig::Validate.
  explicit OrbExtractor(const OrbConfig& config);

  // gray: CV_8UC1 (throws InputError otherwise). On return, keypoints are in
  // level-0 pixels: pt = level pt * scale, octave = level, size = 31 * scale,
  // angle in degrees [0, 360), response = FAST score; descriptors is CV_8U,
  // 32 bytes a row, row i describing keypoints[i]. Keypoints are grouped by
  // level, in a deterministic order; at most config.features of them.
  void Extract(const cv::Mat& gray, std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors);

  // Levels are independent once the pyramid is built: with 2 threads Extract()
  // hands every other level to a helper thread (work taken in level order, so
  // the split balances itself), for the same keypoints and descriptors as with 1.
  // Worth it only when a core is idle (see OrbConfig::threads).
  void set_threads(int threads) { threads_ = threads < 2 ? 1 : 2; }
  int threads() const { return threads_; }

  int levels() const { return static_cast<int>(scales_.scale.size()); }
  const std::vector<double>& scale_factors() const { return scales_.scale; }
  const std::vector<double>& inv_scale_factors() const { return scales_.inv_scale; }
  const std::vector<double>& level_sigma2() const { return scales_.sigma2; }
  const std::vector<double>& inv_level_sigma2() const { return scales_.inv_sigma2; }
  const std::vector<int>& features_per_level() const { return features_per_level_; }
  // The pyramid of the last Extract() (level 0 a copy of its input).
  const std::vector<cv::Mat>& pyramid() const { return pyramid_; }

 private:
  // Keypoints of one level in that level's coordinates, octave 0, and their descriptors.
  // `worker` (0 or 1) picks the BRIEF object.
  void ExtractLevel(int level, int worker, std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors) const;

  OrbConfig config_;
  ScaleLevels scales_;
  std::vector<int> features_per_level_;
  IntensityCentroid orientation_;
  // One rotated-BRIEF object per thread: OpenCV does not promise that
  // concurrent compute() calls on one Feature2D are safe.
  cv::Ptr<cv::ORB> brief_[2];
  int threads_ = 1;
  std::vector<cv::Mat> pyramid_;
};

}  // namespace sgslam::features
