// The immutable per-image feature data shared by a Frame and, when it becomes
// one, its KeyFrame (no copy): keypoints, undistorted keypoints, depth, the
// virtual right coordinate, descriptors and the search grid.
#pragma once

#include <memory>
#include <vector>

#include <opencv2/core.hpp>
#include <Eigen/Core>

#include "sgslam/camera/camera.h"
#include "sgslam/detection/detection.h"
#include "sgslam/map/feature_grid.h"
#include "sgslam/features/pyramid.h"

namespace sgslam {

using ScaleLevels = features::ScaleLevels;

struct Features {
  std::shared_ptr<const Camera> camera;
  std::shared_ptr<const ScaleLevels> scale;
  ImageBounds bounds;
  std::vector<cv::KeyPoint> keys;     // as detected (distorted image)
  std::vector<cv::KeyPoint> keys_un;  // undistorted; all geometry uses these
  std::vector<float> depth;           // m, <= 0: no depth
  std::vector<float> u_right;         // px, u_r = u - bf / d (ORB-SLAM2 RGB-D); < 0: none
  cv::Mat descriptors;                // CV_8U, 32 bytes a row
  FeatureGrid grid;
  // Dynamic feature rejection (paper Algorithm 1): 1 where the keypoint was judged
  // moving (never tracked nor mapped); empty or all 0 in a static run. Keyframes
  // keep it, with the frame's detections, for the semantic mapping thread.
  std::vector<std::uint8_t> dynamic;
  // 1 where a kept keypoint had no geometric test (no flow pair or no F: Algorithm 1
  // had no evidence either way); empty when unknown. The semantic thread does not
  // count such keypoints as static votes (dynamic_mask.h).
  std::vector<std::uint8_t> unjudged;
  std::vector<Detection> detections;
  // rad/s, camera frame: the angular velocity keys_un, depth and u_right were
  // corrected for the rolling shutter with (camera/rolling_shutter.h); zero: none.
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();

  std::size_t size() const { return keys.size(); }
  const std::uint8_t* descriptor(std::size_t i) const { return descriptors.ptr<std::uint8_t>(static_cast<int>(i)); }
  std::vector<std::size_t> InArea(double u, double v, double r, int min_level = -1, int max_level = -1) const {
    return grid.InArea(keys_un, u, v, r, min_level, max_level);
  }
  // The 3-D point of keypoint i in the camera frame (requires depth[i] > 0).
  Eigen::Vector3d Unproject(std::size_t i) const {
    return camera->Unproject(keys_un[i].pt.x, keys_un[i].pt.y, depth[i]);
  }
};

// Undistorts the keypoints, looks up their depth (raw depth image registered to
// the distorted RGB image, as in TUM and Bonn), corrects them for the rolling
// shutter with angular_velocity when the camera has a readout time, and builds the
// grid. dynamic: one label per keypoint, or empty for none.
std::shared_ptr<const Features> MakeFeatures(std::vector<cv::KeyPoint> keys, cv::Mat descriptors,
                                             const cv::Mat& depth_raw, std::shared_ptr<const Camera> camera,
                                             std::shared_ptr<const ScaleLevels> scale,
                                             std::vector<std::uint8_t> dynamic = {},
                                             std::vector<Detection> detections = {},
                                             std::vector<std::uint8_t> unjudged = {},
                                             const Eigen::Vector3d& angular_velocity = Eigen::Vector3d::Zero());

// A copy of f with its keypoints corrected for the rolling shutter again, with a
// better angular velocity (the tracker's, once the frame's pose is known):
// keys_un, depth, u_right and the grid change, keypoint order and everything else stay.
std::shared_ptr<const Features> WithRollingShutterCorrection(const Features& f, const Eigen::Vector3d& angular_velocity);

// Bounds of the undistorted image (corners undistorted).
ImageBounds UndistortedBounds(const Camera& camera);

}  // namespace sgslam
