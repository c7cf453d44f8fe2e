#include "sgslam/camera/camera.h"

#include <opencv2/calib3d.hpp>

namespace sgslam {

Camera::Camera(const CameraConfig& config)
    : config_(config),
      fx_(config.fx),
      fy_(config.fy),
      cx_(config.cx),
      cy_(config.cy),
      inv_depth_factor_(1.0 / config.depth_factor),
      has_distortion_(config.k1 != 0 || config.k2 != 0 || config.p1 != 0 || config.p2 != 0 || config.k3 != 0) {
  K_ = (cv::Mat_<double>(3, 3) << fx_, 0, cx_, 0, fy_, cy_, 0, 0, 1);
  dist_ = (cv::Mat_<double>(1, 5) << config.k1, config.k2, config.p1, config.p2, config.k3);
}

Eigen::Vector2d Camera::Distort(const Eigen::Vector2d& undistorted) const {
  const double x = (undistorted.x() - cx_) / fx_;
  const double y = (undistorted.y() - cy_) / fy_;
  const double r2 = x * x + y * y;
  const double radial = 1 + config_.k1 * r2 + config_.k2 * r2 * r2 + config_.k3 * r2 * r2 * r2;
  const double xd = x * radial + 2 * config_.p1 * x * y + config_.p2 * (r2 + 2 * x * x);
  const double yd = y * radial + config_.p1 * (r2 + 2 * y * y) + 2 * config_.p2 * x * y;
  return {fx_ * xd + cx_, fy_ * yd + cy_};
}

void Camera::Undistort(std::vector<cv::Point2f>& points) const {
  if (!has_distortion_ || points.empty()) return;
  // OpenCV's default 5 iterations leave errors of several pixels in the corners of
  // the strongly distorted TUM fr1 images; iterate to convergence instead.
  std::vector<cv::Point2f> out;
  cv::undistortPoints(points, out, K_, dist_, cv::noArray(), K_,
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 50, 1e-8));
  points.swap(out);
}

}  // namespace sgslam
