// Pose and angular velocity of a rolling-shutter frame from its matches
// (camera/rolling_shutter.h). Its keypoints were corrected with a predicted
// angular velocity; the rows of one image then still disagree by what the
// prediction got wrong, so the error delta is observable within the frame: a
// turn about the vertical axis shears the image, one about the horizontal axis
// stretches it. Differencing poses of consecutive frames gives the velocity of
// the interval between them, half a frame late and with the noise of two poses;
// fitted here it is the frame's own.
//
// Pure function, safe from any thread. The caller passes the inliers of a
// previous pose fit; Huber kernels as in OptimizePose guard the rest.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "sgslam/common/se3.h"
#include "sgslam/optim/pose_optimizer.h"

namespace sgslam::optim {

struct RollingShutterPoseOptions {
  int iterations = 5;         // Levenberg-Marquardt iterations
  double prior_sigma = 1.0;   // rad/s, of delta: keeps it near the prediction when few rows are seen
  double chi2_mono = 5.991;   // Huber thresholds, as in OptimizePose
  double chi2_stereo = 7.815;
};

struct RollingShutterPoseResult {
  SE3 T_c_w;
  Eigen::Vector3d delta = Eigen::Vector3d::Zero();  // rad/s, to add to the velocity the keypoints were corrected with
  bool ok = false;                                  // false: too few observations or no usable solution
};

// row_time: one per observation, seconds from the middle row (RowTimeOffset).
RollingShutterPoseResult OptimizePoseAndAngularVelocity(const SE3& T_c_w_initial,
                                                        const std::vector<PoseObservation>& obs,
                                                        const std::vector<double>& row_time, const Intrinsics& K,
                                                        const RollingShutterPoseOptions& options = {});

}  // namespace sgslam::optim
