#include "sgslam/dynamic/regions.h"

#include <algorithm>

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

}  // namespace sgslam::dynamic
