#include "sgslam/geometry/epipolar.h"

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>

namespace sgslam::geometry {

namespace {

// Pairs within the threshold of their epipolar lines.
int CountInliers(const Eigen::Matrix3d& F, const std::vector<Eigen::Vector2d>& prev,
                 const std::vector<Eigen::Vector2d>& cur, double threshold) {
  int inliers = 0;
  for (size_t i = 0; i < prev.size(); ++i) {
    const double d = EpipolarDistance(F, prev[i], cur[i]);
    inliers += std::isfinite(d) && d <= threshold;
  }
  return inliers;
}

}  // namespace

double EpipolarDistance(const Eigen::Matrix3d& F_cur_prev, const Eigen::Vector2d& prev, const Eigen::Vector2d& cur) {
  const Eigen::Vector3d line = F_cur_prev * prev.homogeneous();          // eq. (2): L2 = F P1
  return std::abs(cur.homogeneous().dot(line)) / line.head<2>().norm();  // eq. (4)
}

std::optional<FundamentalEstimate> EstimateFundamental(const std::vector<Eigen::Vector2d>& prev,
                                                       const std::vector<Eigen::Vector2d>& cur,
                                                       const std::vector<bool>& preferred,
                                                       const FundamentalOptions& options) {
  FundamentalEstimate est;
  const auto n_preferred = static_cast<int>(std::count(preferred.begin(), preferred.end(), true));
  est.from_static = n_preferred >= options.min_preferred;
  std::vector<cv::Point2f> p1, p2;  // OpenCV's order: points1 = previous, points2 = current
  std::vector<Eigen::Vector2d> e1, e2;
  for (size_t i = 0; i < prev.size(); ++i) {
    if (est.from_static && !preferred[i]) continue;
    p1.emplace_back(static_cast<float>(prev[i].x()), static_cast<float>(prev[i].y()));
    p2.emplace_back(static_cast<float>(cur[i].x()), static_cast<float>(cur[i].y()));
    e1.push_back(prev[i]);
    e2.push_back(cur[i]);
  }
  est.pairs = static_cast<int>(p1.size());
  if (est.pairs < 8) return std::nullopt;
  const cv::Mat F_cv = cv::findFundamentalMat(p1, p2, cv::FM_RANSAC, options.threshold, options.confidence,
                                              options.iterations);
  if (F_cv.rows != 3 || F_cv.cols != 3) return std::nullopt;  // no model, or several (7 pairs)
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) est.F_cur_prev(r, c) = F_cv.at<double>(r, c);
  }
  est.F_cur_prev /= est.F_cur_prev.norm();
  est.inliers = CountInliers(est.F_cur_prev, e1, e2, options.threshold);
  return est;
}

Eigen::Matrix3d FundamentalMatrix(const SE3& T_21, const Pinhole& K) {
  Eigen::Matrix3d K_inv;
  K_inv << 1 / K.fx, 0, -K.cx / K.fx, 0, 1 / K.fy, -K.cy / K.fy, 0, 0, 1;
  return K_inv.transpose() * Hat(T_21.translation()) * T_21.rotation() * K_inv;
}

}  // namespace sgslam::geometry
