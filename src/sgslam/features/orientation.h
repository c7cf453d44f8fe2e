// Keypoint orientation by intensity centroid (Rublee et al., ORB, ICCV 2011,
// eqs. 1-3): theta = atan2(m01, m10) with m_pq = sum x^p y^q I(x, y) over a disc
// around the corner. Rotated BRIEF is sampled along theta, which is what makes
// the descriptor rotation invariant.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

namespace sgslam::features {

class IntensityCentroid {
 public:
  // radius: px, the disc (15 for the 31x31 ORB patch).
  explicit IntensityCentroid(int radius);

  // Sets kp.angle (degrees in [0, 360), x right / y down, as OpenCV) for each
  // keypoint, in `image` coordinates; keypoints must be >= radius px inside.
  void Compute(const cv::Mat& image, std::vector<cv::KeyPoint>& keypoints) const;

  // umax[v]: half-width of the disc at row offset |v|.
  const std::vector<int>& umax() const { return umax_; }

 private:
  int radius_;
  std::vector<int> umax_;
};

}  // namespace sgslam::features
