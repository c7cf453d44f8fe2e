#include "sgslam/dynamic/flow_guess.h"

#include <cmath>
#include <utility>

#include "sgslam/common/stats.h"
#include "sgslam/dynamic/depth_sample.h"

namespace sgslam::dynamic {

std::vector<cv::Point2f> PredictPrevious(const std::vector<cv::Point2f>& cur_raw,
                                         const std::vector<cv::Point2f>& cur_un, const FlowPrediction& prediction,
                                         double depth_min, double depth_max) {
  const std::size_t n = cur_raw.size();
  const cv::Mat& depth = prediction.cur_depth;
  std::vector<double> z(n, 0.0);
  std::vector<double> measured;
  measured.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const int x = cvRound(cur_raw[i].x), y = cvRound(cur_raw[i].y);
    if (depth.empty() || x < 0 || y < 0 || x >= depth.cols || y >= depth.rows) continue;
    const double d = DepthAt(depth, x, y, prediction.depth_factor);
    if (std::isfinite(d) && d >= depth_min && d <= depth_max) z[i] = d, measured.push_back(d);
  }
  const double fallback = measured.empty() ? 2.0 : Percentile(std::move(measured), 0.5);  // m, the middle depth
  const Pinhole& K = prediction.K;
  const SE3 T_prev_cur = prediction.T_cur_prev.Inverse();
  std::vector<cv::Point2f> out(cur_raw);
  for (std::size_t i = 0; i < n; ++i) {
    const double zi = z[i] > 0 ? z[i] : fallback;
    const Eigen::Vector3d X((cur_un[i].x - K.cx) / K.fx * zi, (cur_un[i].y - K.cy) / K.fy * zi, zi);
    const Eigen::Vector3d P = T_prev_cur * X;
    if (P.z() < depth_min) continue;  // behind or at the previous camera: no guess, LK starts at the keypoint
    const double u = K.fx * P.x() / P.z() + K.cx, v = K.fy * P.y() / P.z() + K.cy;
    out[i].x = cur_raw[i].x + static_cast<float>(u - cur_un[i].x);
    out[i].y = cur_raw[i].y + static_cast<float>(v - cur_un[i].y);
  }
  return out;
}

}  // namespace sgslam::dynamic
