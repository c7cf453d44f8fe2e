#include "sgslam/dynamic/regions.h"

#include "sgslam/dynamic/depth_sample.h"

#include <algorithm>
#include <cmath>

namespace sgslam::dynamic {

std::vector<double> KeypointWeights(const std::vector<cv::KeyPoint>& keys, const std::vector<Detection>& detections,
                                    const WeightFn& weight) {
  std::vector<double> w(keys.size(), 1.0);
  if (!weight) return w;
  for (const Detection& d : detections) {
    const double wd = weight(d.class_name);
    if (!(wd > 1.0)) continue;  // static class (or NaN): no dynamic region
    for (size_t i = 0; i < keys.size(); ++i) {
      const cv::Point2f& p = keys[i].pt;
      // Half-open box [x, x + width) x [y, y + height), as detection.h defines it.
      if (p.x >= d.box.x && p.x < d.box.x + d.box.width && p.y >= d.box.y && p.y < d.box.y + d.box.height) {
        w[i] = std::max(w[i], wd);
      }
    }
  }
  return w;
}

double BoxObjectDepth(const cv::Rect2f& box, const cv::Mat& depth, double depth_factor, double percentile) {
  if (depth.empty()) return 0;
  constexpr int kGrid = 12;  // samples per axis: 144 pixels, cheap next to the flow
  std::vector<float> z;
  z.reserve(kGrid * kGrid);
  for (int gy = 0; gy < kGrid; ++gy) {
    const float y = box.y + box.height * (0.1f + 0.8f * (gy + 0.5f) / kGrid);
    for (int gx = 0; gx < kGrid; ++gx) {
      const float x = box.x + box.width * (0.25f + 0.5f * (gx + 0.5f) / kGrid);
      const int xi = static_cast<int>(x), yi = static_cast<int>(y);
      if (xi < 0 || yi < 0 || xi >= depth.cols || yi >= depth.rows) continue;
      const double d = DepthAt(depth, xi, yi, depth_factor);
      if (d > 0 && std::isfinite(d)) z.push_back(static_cast<float>(d));
    }
  }
  if (z.size() < 8) return 0;
  const auto k = static_cast<std::ptrdiff_t>(std::clamp(percentile, 0.0, 1.0) * static_cast<double>(z.size() - 1));
  std::nth_element(z.begin(), z.begin() + k, z.end());
  return z[static_cast<size_t>(k)];
}

std::vector<double> KeypointWeightsWithDepth(const std::vector<cv::KeyPoint>& keys,
                                             const std::vector<Detection>& detections, const WeightFn& weight,
                                             const cv::Mat& depth, double depth_factor, double band,
                                             double object_percentile) {
  if (!(band > 0) || depth.empty()) return KeypointWeights(keys, detections, weight);
  std::vector<double> w(keys.size(), 1.0);
  if (!weight) return w;
  for (const Detection& d : detections) {
    const double wd = weight(d.class_name);
    if (!(wd > 1.0)) continue;
    const double z_object = BoxObjectDepth(d.box, depth, depth_factor, object_percentile);
    for (size_t i = 0; i < keys.size(); ++i) {
      const cv::Point2f& p = keys[i].pt;
      if (!(p.x >= d.box.x && p.x < d.box.x + d.box.width && p.y >= d.box.y && p.y < d.box.y + d.box.height)) continue;
      // Keypoints lie in the image; the clamp only guards the rounding.
      const int x = std::clamp(static_cast<int>(p.x), 0, depth.cols - 1);
      const int y = std::clamp(static_cast<int>(p.y), 0, depth.rows - 1);
      const double z = DepthAt(depth, x, y, depth_factor);
      const bool behind = z_object > 0 && z > 0 && std::isfinite(z) && z > z_object + band;
      if (!behind) w[i] = std::max(w[i], wd);
    }
  }
  return w;
}

}  // namespace sgslam::dynamic
