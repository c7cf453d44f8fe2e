// Rolling shutter of the colour camera. The Kinect v1 colour sensor (TUM RGB-D)
// exposes its rows one after the other over about one frame time, so in a fast
// turn the top and bottom of one image see the scene from cameras several
// pixels of rotation apart (docs/rolling-shutter.md).
//
// Model: row v of the raw (distorted) image is exposed at t + (v / height - 1/2)
// * readout, t the frame time, taken as the middle row's. Turning at angular
// velocity w (camera frame, rad/s: R_w_c(t + s) = R_w_c(t) Exp(w s)), a point
// seen along bearing b at its row time lies along Exp(w s) b in the middle-row
// camera. Translation during the readout is left out: at walking speed it moves
// the camera by millimetres, a rotation of 1 rad/s by 15 mrad, 8 px.
#pragma once

#include <optional>
#include <vector>

#include <opencv2/core/types.hpp>
#include <Eigen/Core>

#include "sgslam/common/se3.h"

namespace sgslam {

class Camera;

// Seconds from the middle row's exposure to raw row v's.
inline double RowTimeOffset(double raw_row, int height, double readout) {
  return (raw_row / height - 0.5) * readout;
}

// The camera-frame angular velocity (rad/s) of a motion T_cur_last that took dt
// seconds (the tracker's constant-velocity model); none when dt is not positive.
std::optional<Eigen::Vector3d> AngularVelocity(const SE3& T_cur_last, double dt);

// Moves undistorted keypoints, and the depth of those with one, from their row
// time to the middle-row camera (see above). from: the angular velocity they were
// already corrected with (zero for raw keypoints), so that keypoints can be
// corrected again with a better estimate; to: the new one. raw: the keypoints as
// detected, whose rows set the times. Points with depth are moved as 3-D points
// (their depth changes by up to ~2 % at the image edge in a fast turn).
void CorrectRollingShutter(const Camera& camera, const std::vector<cv::KeyPoint>& raw, const Eigen::Vector3d& from,
                           const Eigen::Vector3d& to, std::vector<cv::KeyPoint>& undistorted,
                           std::vector<float>& depth);

}  // namespace sgslam
