#include "sgslam/dynamic/motion.h"

#include "sgslam/dynamic/depth_sample.h"
#include "sgslam/geometry/pnp.h"

#include <algorithm>
#include <cmath>

namespace sgslam::dynamic {

namespace {

// The PnP RANSAC of the RGB-D check (R5), geometry::PnpOptions' defaults; not
// measured on their own (docs/algorithm1.md, R5).
constexpr double kMotionThreshold = 2.0;  // px, inlier reprojection error: twice F's 1 px, as depth noise adds
constexpr int kMotionIterations = 100;    // RANSAC iterations at most: the static pairs outnumber the movers

}  // namespace

std::optional<MotionEstimate> EstimateMotion(const std::vector<cv::Point2f>& prev_raw,
                                             const std::vector<cv::Point2f>& prev_un,
                                             const std::vector<cv::Point2f>& cur_un, const std::vector<bool>& use,
                                             const cv::Mat& prev_depth, double depth_factor, const Pinhole& K) {
  if (prev_depth.empty()) return std::nullopt;
  std::vector<cv::Point3f> object;
  std::vector<cv::Point2f> image;
  for (size_t i = 0; i < prev_raw.size(); ++i) {
    if (!use[i]) continue;
    const int x = cvRound(prev_raw[i].x), y = cvRound(prev_raw[i].y);
    if (x < 0 || y < 0 || x >= prev_depth.cols || y >= prev_depth.rows) continue;
    const double z = DepthAt(prev_depth, x, y, depth_factor);
    if (!std::isfinite(z) || z < kDepthMin || z > kDepthMax) continue;
    object.emplace_back(static_cast<float>((prev_un[i].x - K.cx) / K.fx * z),
                        static_cast<float>((prev_un[i].y - K.cy) / K.fy * z), static_cast<float>(z));
    image.push_back(cur_un[i]);
  }
  MotionEstimate est;
  est.pairs = static_cast<int>(object.size());
  const auto T = geometry::SolvePnP(object, image, K,
                                    {kMotionIterations, kMotionThreshold, kMotionMinInliers});
  if (!T) return std::nullopt;
  est.T_cur_prev = *T;
  // Count the inliers of the refined model.
  for (size_t j = 0; j < object.size(); ++j) {
    const Eigen::Vector3d p = *T * Eigen::Vector3d(object[j].x, object[j].y, object[j].z);
    if (p.z() <= 0) continue;
    const double du = K.fx * p.x() / p.z() + K.cx - image[j].x, dv = K.fy * p.y() / p.z() + K.cy - image[j].y;
    est.inliers += std::hypot(du, dv) <= kMotionThreshold;
  }
  return est;
}

}  // namespace sgslam::dynamic
