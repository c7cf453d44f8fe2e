#include "sgslam/dynamic/epipolar.h"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>

namespace sgslam::dynamic {

namespace {

// Hartley normalisation: centroid to the origin, mean distance sqrt(2).
Eigen::Matrix3d Normaliser(const std::vector<Eigen::Vector2d>& p) {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& x : p) mean += x;
  mean /= static_cast<double>(p.size());
  double spread = 0;
  for (const auto& x : p) spread += (x - mean).norm();
  const double s = std::sqrt(2.0) * static_cast<double>(p.size()) / std::max(spread, 1e-12);
  Eigen::Matrix3d T;
  T << s, 0, -s * mean.x(), 0, s, -s * mean.y(), 0, 0, 1;
  return T;
}

// MSAC cost: sum of squared distances truncated at the threshold.
double Cost(const Eigen::Matrix3d& F, const std::vector<Eigen::Vector2d>& prev, const std::vector<Eigen::Vector2d>& cur,
            double threshold, int* inliers) {
  double cost = 0;
  *inliers = 0;
  for (size_t i = 0; i < prev.size(); ++i) {
    const double d = EpipolarDistance(F, prev[i], cur[i]);
    const bool in = std::isfinite(d) && d <= threshold;
    *inliers += in;
    cost += in ? d * d : threshold * threshold;
  }
  return cost;
}

}  // namespace

double EpipolarDistance(const Eigen::Matrix3d& F_cur_prev, const Eigen::Vector2d& prev, const Eigen::Vector2d& cur) {
  const Eigen::Vector3d line = F_cur_prev * prev.homogeneous();          // eq. (2): L2 = F P1
  return std::abs(cur.homogeneous().dot(line)) / line.head<2>().norm();  // eq. (4)
}

Eigen::Matrix3d FundamentalEightPoint(const std::vector<Eigen::Vector2d>& prev,
                                      const std::vector<Eigen::Vector2d>& cur) {
  const Eigen::Matrix3d T1 = Normaliser(prev), T2 = Normaliser(cur);
  // Normal equations of A f = 0, one row per pair (x2^T F x1 = 0); the 9x9 system is
  // solved by its smallest eigenvector, which costs O(n) whatever the pair count.
  Eigen::Matrix<double, 9, 9> AtA = Eigen::Matrix<double, 9, 9>::Zero();
  for (size_t i = 0; i < prev.size(); ++i) {
    const Eigen::Vector3d a = T1 * prev[i].homogeneous(), b = T2 * cur[i].homogeneous();
    Eigen::Matrix<double, 9, 1> row;
    row << b.x() * a, b.y() * a, b.z() * a;
    AtA.selfadjointView<Eigen::Lower>().rankUpdate(row);
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 9, 9>> eig(AtA.selfadjointView<Eigen::Lower>());
  const Eigen::Matrix<double, 9, 1> f = eig.eigenvectors().col(0);
  Eigen::Matrix3d Fn;
  Fn << f(0), f(1), f(2), f(3), f(4), f(5), f(6), f(7), f(8);
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(Fn, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Vector3d s = svd.singularValues();
  s(2) = 0;  // rank 2: all epipolar lines meet in the epipole
  const Eigen::Matrix3d F = T2.transpose() * svd.matrixU() * s.asDiagonal() * svd.matrixV().transpose() * T1;
  return F / F.norm();
}

std::optional<FundamentalEstimate> EstimateFundamental(const std::vector<Eigen::Vector2d>& prev,
                                                       const std::vector<Eigen::Vector2d>& cur,
                                                       const std::vector<bool>& preferred,
                                                       const DynamicConfig& config) {
  FundamentalEstimate est;
  const auto n_preferred = static_cast<int>(std::count(preferred.begin(), preferred.end(), true));
  est.from_static = n_preferred >= config.min_static_pairs;
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
  std::vector<uchar> mask;
  const cv::Mat F_cv = cv::findFundamentalMat(p1, p2, cv::FM_RANSAC, config.ransac_threshold, config.ransac_confidence,
                                              config.ransac_iterations, mask);
  if (F_cv.rows != 3 || F_cv.cols != 3) return std::nullopt;  // no model, or several (7 pairs)
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) est.F_cur_prev(r, c) = F_cv.at<double>(r, c);
  }
  est.F_cur_prev /= est.F_cur_prev.norm();
  const double cost = Cost(est.F_cur_prev, e1, e2, config.ransac_threshold, &est.inliers);
  if (config.refine_fundamental) {
    std::vector<Eigen::Vector2d> in1, in2;
    for (size_t i = 0; i < mask.size(); ++i) {
      if (mask[i]) {
        in1.push_back(e1[i]);
        in2.push_back(e2[i]);
      }
    }
    if (in1.size() >= 8) {
      const Eigen::Matrix3d F = FundamentalEightPoint(in1, in2);
      int inliers = 0;
      const double refit_cost = Cost(F, e1, e2, config.ransac_threshold, &inliers);
      if (refit_cost <= cost) {  // the refit can only replace the RANSAC model when it fits better
        est.F_cur_prev = F;
        est.inliers = inliers;
      }
    }
  }
  return est;
}

Eigen::Matrix3d FundamentalFromPose(const SE3& T_cur_prev, const Eigen::Matrix3d& K) {
  const Eigen::Matrix3d K_inv = K.inverse();
  const Eigen::Matrix3d F = K_inv.transpose() * Hat(T_cur_prev.translation()) * T_cur_prev.rotation() * K_inv;
  return F / F.norm();
}

}  // namespace sgslam::dynamic
