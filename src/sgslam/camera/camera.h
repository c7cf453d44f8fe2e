// Pinhole camera with OpenCV's radial-tangential distortion (k1 k2 p1 p2 k3) and
// the RGB-D depth encoding. Keypoints are undistorted once, after detection; all
// geometry downstream works on undistorted pixel coordinates.
#pragma once

#include <opencv2/core.hpp>
#include <Eigen/Core>
#include <vector>

#include "sgslam/camera/camera_config.h"

namespace sgslam {

class Camera {
 public:
  explicit Camera(const CameraConfig& config);

  // Undistorted pixel <-> normalised/metric geometry (pinhole only).
  Eigen::Vector2d Project(const Eigen::Vector3d& p_c) const {
    return {fx_ * p_c.x() / p_c.z() + cx_, fy_ * p_c.y() / p_c.z() + cy_};
  }
  Eigen::Vector3d Unproject(double u, double v, double depth_m) const {
    return {(u - cx_) / fx_ * depth_m, (v - cy_) / fy_ * depth_m, depth_m};
  }

  // Applies the lens distortion to an undistorted pixel (the forward model).
  Eigen::Vector2d Distort(const Eigen::Vector2d& undistorted) const;
  // Removes the lens distortion, in place; iterates to sub-1e-3 px accuracy.
  void Undistort(std::vector<cv::Point2f>& points) const;

  // Metres from a raw 16-bit depth value; 0 means no measurement.
  double DepthMetres(std::uint16_t raw) const { return raw * inv_depth_factor_; }

  bool has_distortion() const { return has_distortion_; }
  int width() const { return config_.width; }
  int height() const { return config_.height; }
  double fx() const { return fx_; }
  double fy() const { return fy_; }
  double cx() const { return cx_; }
  double cy() const { return cy_; }
  double baseline_fx() const { return config_.baseline_fx; }
  const CameraConfig& config() const { return config_; }

 private:
  CameraConfig config_;
  double fx_, fy_, cx_, cy_, inv_depth_factor_;
  bool has_distortion_;
  cv::Mat K_, dist_;
};

}  // namespace sgslam
