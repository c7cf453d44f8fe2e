// Scale pyramid of the ORB extractor (ORB-SLAM2's design): level 0 is the input
// grey image and level l is level l-1 shrunk by 1/scale_factor, so a keypoint
// found at level l covers a patch scale_factor^l times larger in the image.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

namespace sgslam::features {

// Per-level factors that tracking and bundle adjustment weight observations by:
// a keypoint at level l has pixel noise proportional to scale[l], so its
// information is inv_sigma2[l] = 1 / scale[l]^2.
struct ScaleLevels {
  int levels = 0;
  double factor = 1.0;      // scale_factor
  double log_factor = 0.0;  // log(scale_factor), for predicting a level from a distance ratio
  std::vector<double> scale;       // scale_factor^l
  std::vector<double> inv_scale;   // 1 / scale[l]
  std::vector<double> sigma2;      // scale[l]^2
  std::vector<double> inv_sigma2;  // 1 / sigma2[l]
};

ScaleLevels MakeScaleLevels(double scale_factor, int levels);

// ORB-SLAM2's geometric split: level l gets N (1 - 1/s) / (1 - (1/s)^L) (1/s)^l
// keypoints, i.e. in proportion to its side length, the last level the
// remainder, so the levels sum to exactly `features`.
std::vector<int> FeaturesPerLevel(int features, double scale_factor, int levels);

// Fills `pyramid` (levels = inv_scale.size()), reusing its buffers across
// frames. Level 0 is a copy of `gray`, so the pyramid outlives the caller's image.
// Level sizes are cvRound(size * inv_scale[l]), each resized bilinearly from the
// level above (resizing from level 0 each time would alias more at coarse levels).
void BuildPyramid(const cv::Mat& gray, const std::vector<double>& inv_scale, std::vector<cv::Mat>& pyramid);

}  // namespace sgslam::features
