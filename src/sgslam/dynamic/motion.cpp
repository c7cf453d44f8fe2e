#include "sgslam/dynamic/motion.h"

#include <opencv2/calib3d.hpp>

namespace sgslam::dynamic {

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
    const double z = prev_depth.type() == CV_16U ? prev_depth.at<std::uint16_t>(y, x) / depth_factor
                                                 : static_cast<double>(prev_depth.at<float>(y, x));
    if (!std::isfinite(z) || z < config.depth_min || z > config.depth_max) continue;
    object.emplace_back(static_cast<float>((prev_un[i].x - K.cx) / K.fx * z),
                        static_cast<float>((prev_un[i].y - K.cy) / K.fy * z), static_cast<float>(z));
    image.push_back(cur_un[i]);
  }
  MotionEstimate est;
  est.pairs = static_cast<int>(object.size());
  if (est.pairs < std::max(config.motion_min_inliers, 6)) return std::nullopt;
  const cv::Matx33d Kcv(K.fx, 0, K.cx, 0, K.fy, K.cy, 0, 0, 1);
  cv::Mat rvec, tvec;
  std::vector<int> inliers;
  if (!cv::solvePnPRansac(object, image, Kcv, cv::noArray(), rvec, tvec, false, config.motion_iterations,
                          static_cast<float>(config.motion_threshold), 0.99, inliers, cv::SOLVEPNP_AP3P) ||
      static_cast<int>(inliers.size()) < config.motion_min_inliers) {
    return std::nullopt;
  }
  std::vector<cv::Point3f> in_object;
  std::vector<cv::Point2f> in_image;
  for (int j : inliers) in_object.push_back(object[j]), in_image.push_back(image[j]);
  cv::solvePnPRefineLM(in_object, in_image, Kcv, cv::noArray(), rvec, tvec);
  // Count the inliers of the refined model.
  std::vector<cv::Point2f> projected;
  cv::projectPoints(object, rvec, tvec, Kcv, cv::noArray(), projected);
  est.inliers = 0;
  for (size_t j = 0; j < object.size(); ++j) est.inliers += cv::norm(projected[j] - image[j]) <= config.motion_threshold;
  cv::Matx33d R;
  cv::Rodrigues(rvec, R);
  Eigen::Matrix3d Re;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) Re(r, c) = R(r, c);
  }
  est.T_cur_prev = SE3(Re, Eigen::Vector3d(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2)));
  return est;
}

}  // namespace sgslam::dynamic
