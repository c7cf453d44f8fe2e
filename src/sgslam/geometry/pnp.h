// The camera pose from 3-D points and their pixels (PnP), shared by the RGB-D check
// of the rejection (dynamic/motion.h) and tracking's recovery after a loss.
// RANSAC: cv::solvePnPRansac with SOLVEPNP_AP3P minimal sets (OpenCV seeds its
// generator the same way on every call, so equal inputs give equal results), then
// a Levenberg-Marquardt refit (cv::solvePnPRefineLM) on the inliers.
// Thread safety: a free function on const inputs.
#pragma once

#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "sgslam/common/se3.h"
#include "sgslam/geometry/pinhole.h"

namespace sgslam::geometry {

struct PnpOptions {
  int iterations = 100;    // RANSAC iterations at most
  double threshold = 2.0;  // px, inlier reprojection error
  int min_inliers = 30;    // fewer: no pose
};

// T_c_o, the pose that maps the object points into the camera whose undistorted
// pixels `image` are. nullopt when fewer than max(min_inliers, 6) points or
// min_inliers inliers.
std::optional<SE3> SolvePnP(const std::vector<cv::Point3f>& object, const std::vector<cv::Point2f>& image,
                            const Pinhole& K, const PnpOptions& options);

}  // namespace sgslam::geometry
