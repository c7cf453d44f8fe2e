#include "sgslam/geometry/rigid.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <utility>

namespace sgslam::geometry {
namespace {

// A sample whose points are (nearly) collinear in either camera leaves the
// rotation about their line free; it is skipped. Sine of the angle at the first point.
constexpr double kMinSampleSine = 1e-3;

bool Collinear(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d u = b - a, v = c - a;
  return !(u.cross(v).norm() > kMinSampleSine * u.norm() * v.norm());
}

// Squared reprojection error of p (in the camera of K) against uv; false behind the camera.
bool Reprojects(const Pinhole& K, const Eigen::Vector3d& p, const Eigen::Vector2d& uv, double max_sq_error) {
  return p.z() > 0 && (K.Project(p) - uv).squaredNorm() < max_sq_error;
}

// Sim3Solver::CheckInliers with scale 1, plus the depth test. Returns the inlier count.
int Classify(const RigidRansacProblem& pb, const SE3& T_12, std::vector<bool>& inlier) {
  const Eigen::Matrix3d R_12 = T_12.rotation(), R_21 = R_12.transpose();
  const Eigen::Vector3d t_12 = T_12.translation(), t_21 = -(R_21 * t_12);
  int n = 0;
  inlier.assign(pb.matches.size(), false);
  for (std::size_t i = 0; i < pb.matches.size(); ++i) {
    const RigidCorrespondence& m = pb.matches[i];
    inlier[i] = Reprojects(pb.K1, R_12 * m.p_c2 + t_12, m.uv1, m.max_sq_error1) &&
                Reprojects(pb.K2, R_21 * m.p_c1 + t_21, m.uv2, m.max_sq_error2);
    n += inlier[i] ? 1 : 0;
  }
  return n;
}

// Samples that give at least one all-inlier minimal set with `probability` when
// a fraction w of the matches are inliers (ORB-SLAM2's SetRansacParameters with
// w = min_inliers / N; here w also grows with the best count so far).
int NeededIterations(double w, double probability, int max_iterations) {
  if (w >= 1.0) return 1;
  if (probability >= 1.0 || w <= 0.0) return max_iterations;
  const double n = std::ceil(std::log(1.0 - probability) / std::log(1.0 - w * w * w));
  return std::clamp(static_cast<int>(std::min(n, 1e9)), 1, max_iterations);
}

// T_12 fitted on the matches use[0], use[1], ... Each pair weighs 1 / (|p_c1|^2 +
// |p_c2|^2): the residual then approximates an angle, the unit of the inlier test;
// unweighted, the depth noise of far points (~ z^2 for RGB-D) drags the fit and
// near points fail the test.
SE3 FitOn(const RigidRansacProblem& pb, const std::vector<std::size_t>& use) {
  std::vector<Eigen::Vector3d> p_c2, p_c1;
  std::vector<double> w;
  for (std::size_t i : use) {
    const RigidCorrespondence& m = pb.matches[i];
    p_c2.push_back(m.p_c2);
    p_c1.push_back(m.p_c1);
    w.push_back(1.0 / (m.p_c1.squaredNorm() + m.p_c2.squaredNorm()));
  }
  return AlignRigid(p_c2, p_c1, w);
}

std::vector<std::size_t> Indices(const std::vector<bool>& mask) {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < mask.size(); ++i)
    if (mask[i]) out.push_back(i);
  return out;
}

}  // namespace

SE3 AlignRigid(const std::vector<Eigen::Vector3d>& model, const std::vector<Eigen::Vector3d>& data,
               const std::vector<double>& weights) {
  const auto weight = [&](std::size_t i) { return weights.empty() ? 1.0 : weights[i]; };
  Eigen::Vector3d model_mean = Eigen::Vector3d::Zero(), data_mean = Eigen::Vector3d::Zero();
  double sum = 0;
  for (std::size_t i = 0; i < model.size(); ++i) {
    model_mean += weight(i) * model[i];
    data_mean += weight(i) * data[i];
    sum += weight(i);
  }
  model_mean /= sum;
  data_mean /= sum;
  // evaluate_ate.py: W = sum model_c data_c^T, U d Vh = svd(W^T), R = U S Vh.
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < model.size(); ++i) {
    H += weight(i) * (data[i] - data_mean) * (model[i] - model_mean).transpose();
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d S = Eigen::Matrix3d::Identity();
  // A reflection fits coplanar or noisy points better than any rotation; forbid it.
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0) S(2, 2) = -1;
  const Eigen::Matrix3d R = svd.matrixU() * S * svd.matrixV().transpose();
  return SE3(R, data_mean - R * model_mean);
}

std::optional<RigidRansacResult> EstimateRigidRansac(const RigidRansacProblem& pb, const RigidRansacOptions& options) {
  const std::size_t n = pb.matches.size();
  if (n < 3 || static_cast<int>(n) < options.min_inliers) return std::nullopt;
  std::mt19937 rng(options.seed);
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  RigidRansacResult best;
  std::vector<bool> inlier;
  int budget =
      NeededIterations(static_cast<double>(options.min_inliers) / n, options.probability, options.max_iterations);
  while (best.iterations < budget) {
    ++best.iterations;
    // Three distinct matches: a partial Fisher-Yates shuffle of `order`.
    for (std::size_t k = 0; k < 3; ++k) {
      std::swap(order[k], order[std::uniform_int_distribution<std::size_t>(k, n - 1)(rng)]);
    }
    const RigidCorrespondence &a = pb.matches[order[0]], &b = pb.matches[order[1]], &c = pb.matches[order[2]];
    if (Collinear(a.p_c1, b.p_c1, c.p_c1) || Collinear(a.p_c2, b.p_c2, c.p_c2)) continue;
    const SE3 T_12 = FitOn(pb, {order[0], order[1], order[2]});
    const int count = Classify(pb, T_12, inlier);
    if (count <= best.inliers) continue;
    best.T_12 = T_12;
    best.inliers = count;
    best.inlier = inlier;
    const double w = static_cast<double>(std::max(count, options.min_inliers)) / n;
    budget = NeededIterations(w, options.probability, options.max_iterations);
  }
  if (best.inliers < std::max(options.min_inliers, 3)) return std::nullopt;

  // Refit on every inlier. A refit that loses inliers keeps the sample's transform.
  const SE3 T_refit = FitOn(pb, Indices(best.inlier));
  const int count = Classify(pb, T_refit, inlier);
  if (count >= best.inliers) {
    best.T_12 = T_refit;
    best.inliers = count;
    best.inlier = std::move(inlier);
  }
  return best;
}

}  // namespace sgslam::geometry
