#include "sgslam/semantic/background_planes.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <random>

namespace sgslam {

namespace {

// Least-squares plane through points: normal = eigenvector of the smallest
// eigenvalue of their covariance.
bool RefinePlane(const std::vector<Eigen::Vector3f>& points, const std::vector<std::size_t>& inliers, Plane& plane) {
  if (inliers.size() < 3) return false;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (std::size_t i : inliers) mean += points[i].cast<double>();
  mean /= static_cast<double>(inliers.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (std::size_t i : inliers) {
    const Eigen::Vector3d d = points[i].cast<double>() - mean;
    cov += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  if (eig.info() != Eigen::Success) return false;
  const Eigen::Vector3d n = eig.eigenvectors().col(0).normalized();
  plane.normal = n.cast<float>();
  plane.offset = static_cast<float>(-n.dot(mean));
  return true;
}

}  // namespace

std::vector<Plane> FitPlanes(const std::vector<Eigen::Vector3f>& points, const PlaneFitOptions& options) {
  std::vector<Plane> planes;
  std::vector<std::size_t> left(points.size());
  for (std::size_t i = 0; i < left.size(); ++i) left[i] = i;
  const auto needed = static_cast<std::size_t>(
      std::max<double>(options.min_points, std::ceil(options.min_share * static_cast<double>(points.size()))));
  std::mt19937 rng(12345);
  while (static_cast<int>(planes.size()) < options.max_planes && left.size() >= needed && left.size() >= 3) {
    std::uniform_int_distribution<std::size_t> pick(0, left.size() - 1);
    Plane best;
    std::size_t best_count = 0;
    for (int it = 0; it < options.iterations; ++it) {
      const Eigen::Vector3f& a = points[left[pick(rng)]];
      const Eigen::Vector3f& b = points[left[pick(rng)]];
      const Eigen::Vector3f& c = points[left[pick(rng)]];
      const Eigen::Vector3f n = (b - a).cross(c - a);
      if (n.norm() < 1e-6f) continue;  // collinear or repeated draw
      Plane candidate{n.normalized(), 0};
      candidate.offset = -candidate.normal.dot(a);
      std::size_t count = 0;
      for (std::size_t i : left) count += OnPlane(candidate, points[i], options);
      if (count > best_count) {
        best_count = count;
        best = candidate;
      }
    }
    if (best_count < needed) break;
    std::vector<std::size_t> inliers, rest;
    for (std::size_t i : left) (OnPlane(best, points[i], options) ? inliers : rest).push_back(i);
    Plane refined = best;
    if (RefinePlane(points, inliers, refined)) {
      // Keep the refinement only when it explains at least as many points.
      std::size_t count = 0;
      for (std::size_t i : left) count += OnPlane(refined, points[i], options);
      if (count >= inliers.size()) {
        best = refined;
        inliers.clear();
        rest.clear();
        for (std::size_t i : left) (OnPlane(best, points[i], options) ? inliers : rest).push_back(i);
      }
    }
    planes.push_back(best);
    left.swap(rest);
  }
  return planes;
}

}  // namespace sgslam
