#include "sgslam/features/orientation.h"

#include <cmath>
#include <numbers>

namespace sgslam::features {

IntensityCentroid::IntensityCentroid(int radius) : radius_(radius) {
  // The disc is the pixels with u^2 + v^2 <= r^2 + r (centres within about
  // r + 0.5). That set is symmetric under swapping u and v, so a patch rotated
  // by 90 degrees covers the same pixels and its angle turns by exactly 90.
  const int limit = radius * radius + radius;
  for (int v = 0; v <= radius; ++v) {
    int u = 0;
    while ((u + 1) * (u + 1) + v * v <= limit) ++u;
    umax_.push_back(u);
  }
}

void IntensityCentroid::Compute(const cv::Mat& image, std::vector<cv::KeyPoint>& keypoints) const {
  const auto step = static_cast<ptrdiff_t>(image.step1());
  for (cv::KeyPoint& kp : keypoints) {
    const uchar* centre = image.ptr<uchar>(cvRound(kp.pt.y)) + cvRound(kp.pt.x);
    long m01 = 0, m10 = 0;
    // Row v and row -v together: their m10 terms add, their m01 terms subtract.
    for (int u = -umax_[0]; u <= umax_[0]; ++u) m10 += u * centre[u];
    for (int v = 1; v <= radius_; ++v) {
      const uchar* below = centre + v * step;
      const uchar* above = centre - v * step;
      const int d = umax_[static_cast<size_t>(v)];
      for (int u = -d; u <= d; ++u) {
        m10 += u * (below[u] + above[u]);
        m01 += v * (below[u] - above[u]);
      }
    }
    double deg = std::atan2(static_cast<double>(m01), static_cast<double>(m10)) * 180.0 / std::numbers::pi;
    if (deg < 0.0) deg += 360.0;
    float angle = static_cast<float>(deg);
    if (angle >= 360.0f) angle = 0.0f;  // rounding of -tiny + 360 to float
    kp.angle = angle;
  }
}

}  // namespace sgslam::features
