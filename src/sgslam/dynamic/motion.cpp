#include "sgslam/dynamic/motion.h"

#include "sgslam/dynamic/depth_sample.h"

#include <opencv2/calib3d.hpp>

#include <algorithm>
#include <cmath>

namespace sgslam::dynamic {

std::optional<SE3> SolvePnPMotion(const std::vector<cv::Point3f>& object, const std::vector<cv::Point2f>& image,
                                  const Pinhole& K, int iterations, double threshold, int min_inliers) {
  if (static_cast<int>(object.size()) < std::max(min_inliers, 6)) return std::nullopt;
  const cv::Matx33d Kcv(K.fx, 0, K.cx, 0, K.fy, K.cy, 0, 0, 1);
  cv::Mat rvec, tvec;
  std::vector<int> inliers;
  if (!cv::solvePnPRansac(object, image, Kcv, cv::noArray(), rvec, tvec, false, iterations,
                          static_cast<float>(threshold), 0.99, inliers, cv::SOLVEPNP_AP3P) ||
      static_cast<int>(inliers.size()) < min_inliers) {
    return std::nullopt;
  }
  std::vector<cv::Point3f> in_object;
  std::vector<cv::Point2f> in_image;
  for (int j : inliers) in_object.push_back(object[j]), in_image.push_back(image[j]);
  cv::solvePnPRefineLM(in_object, in_image, Kcv, cv::noArray(), rvec, tvec);
  cv::Matx33d R;
  cv::Rodrigues(rvec, R);
  Eigen::Matrix3d Re;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) Re(r, c) = R(r, c);
  }
  return SE3(Re, Eigen::Vector3d(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2)));
}

std::optional<MotionEstimate> EstimateMotion(const std::vector<cv::Point2f>& prev_raw,
                                             const std::vector<cv::Point2f>& prev_un,
                                             const std::vector<cv::Point2f>& cur_un, const std::vector<bool>& use,
                                             const cv::Mat& prev_depth, double depth_factor, const Pinhole& K,
                                             const DynamicConfig& config) {
  if (prev_depth.empty()) return std::nullopt;
  std::vector<cv::Point3f> object;
  std::vector<cv::Point2f> image;
  for (size_t i = 0; i < prev_raw.size(); ++i) {
    if (!use[i]) continue;
    const int x = cvRound(prev_raw[i].x), y = cvRound(prev_raw[i].y);
    if (x < 0 || y < 0 || x >= prev_depth.cols || y >= prev_depth.rows) continue;
    const double z = DepthAt(prev_depth, x, y, depth_factor);
    if (!std::isfinite(z) || z < config.depth_min || z > config.depth_max) continue;
    object.emplace_back(static_cast<float>((prev_un[i].x - K.cx) / K.fx * z),
                        static_cast<float>((prev_un[i].y - K.cy) / K.fy * z), static_cast<float>(z));
    image.push_back(cur_un[i]);
  }
  MotionEstimate est;
  est.pairs = static_cast<int>(object.size());
  const auto T = SolvePnPMotion(object, image, K, config.motion_iterations, config.motion_threshold,
                                config.motion_min_inliers);
  if (!T) return std::nullopt;
  est.T_cur_prev = *T;
  // Count the inliers of the refined model.
  for (size_t j = 0; j < object.size(); ++j) {
    const Eigen::Vector3d p = *T * Eigen::Vector3d(object[j].x, object[j].y, object[j].z);
    if (p.z() <= 0) continue;
    const double du = K.fx * p.x() / p.z() + K.cx - image[j].x, dv = K.fy * p.y() / p.z() + K.cy - image[j].y;
    est.inliers += std::hypot(du, dv) <= config.motion_threshold;
  }
  return est;
}

}  // namespace sgslam::dynamic
