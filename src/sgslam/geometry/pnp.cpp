#include "sgslam/geometry/pnp.h"

#include <algorithm>

#include <opencv2/calib3d.hpp>

namespace sgslam::geometry {

std::optional<SE3> SolvePnP(const std::vector<cv::Point3f>& object, const std::vector<cv::Point2f>& image,
                            const Pinhole& K, const PnpOptions& options) {
  if (static_cast<int>(object.size()) < std::max(options.min_inliers, 6)) return std::nullopt;
  const cv::Matx33d Kcv(K.fx, 0, K.cx, 0, K.fy, K.cy, 0, 0, 1);
  cv::Mat rvec, tvec;
  std::vector<int> inliers;
  if (!cv::solvePnPRansac(object, image, Kcv, cv::noArray(), rvec, tvec, false, options.iterations,
                          static_cast<float>(options.threshold), 0.99, inliers, cv::SOLVEPNP_AP3P) ||
      static_cast<int>(inliers.size()) < options.min_inliers) {
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

}  // namespace sgslam::geometry
