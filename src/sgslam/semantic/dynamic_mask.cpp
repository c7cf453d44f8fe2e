#include "sgslam/semantic/dynamic_mask.h"

#include <algorithm>
#include <cmath>

namespace sgslam {

cv::Mat DynamicPixelMask(const cv::Mat& depth_raw, double depth_factor, const std::vector<Detection>& detections,
                         const ClassTable& classes, const std::vector<cv::KeyPoint>& keys,
                         const std::vector<std::uint8_t>& rejected, const SemanticConfig& config) {
  cv::Mat mask = cv::Mat::zeros(depth_raw.size(), CV_8UC1);
  const cv::Rect image(0, 0, depth_raw.cols, depth_raw.rows);
  std::vector<cv::Rect> boxes;
  for (const Detection& d : detections) {
    if (!classes.is_dynamic(d.class_name)) continue;
    const float mx = d.box.width * static_cast<float>(config.box_margin);
    const float my = d.box.height * static_cast<float>(config.box_margin);
    const cv::Rect grown(cv::Point(static_cast<int>(std::floor(d.box.x - mx)), static_cast<int>(std::floor(d.box.y - my))),
                         cv::Point(static_cast<int>(std::ceil(d.box.x + d.box.width + mx)),
                                   static_cast<int>(std::ceil(d.box.y + d.box.height + my))));
    const cv::Rect r = grown & image;
    if (r.area() <= 0) continue;
    mask(r).setTo(255);
    boxes.push_back(r);
  }
  if (rejected.size() != keys.size() || config.motion_radius <= 0) return mask;
  const int radius = config.motion_radius;
  const double band_raw = config.motion_depth_band * depth_factor;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    if (!rejected[i]) continue;
    const int u = cvRound(keys[i].pt.x), v = cvRound(keys[i].pt.y);
    if (!image.contains({u, v}) || mask.at<std::uint8_t>(v, u) != 0) continue;  // inside a dynamic box already
    const double z = depth_raw.at<std::uint16_t>(v, u);
    if (z <= 0) continue;
    const int v0 = std::max(0, v - radius), v1 = std::min(depth_raw.rows - 1, v + radius);
    const int u0 = std::max(0, u - radius), u1 = std::min(depth_raw.cols - 1, u + radius);
    for (int y = v0; y <= v1; ++y) {
      const std::uint16_t* d = depth_raw.ptr<std::uint16_t>(y);
      std::uint8_t* m = mask.ptr<std::uint8_t>(y);
      const int dy = y - v;
      for (int x = u0; x <= u1; ++x) {
        const int dx = x - u;
        if (dx * dx + dy * dy > radius * radius || d[x] == 0) continue;
        if (std::abs(static_cast<double>(d[x]) - z) <= band_raw) m[x] = 255;
      }
    }
  }
  return mask;
}

}  // namespace sgslam
