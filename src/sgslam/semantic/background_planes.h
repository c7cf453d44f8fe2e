// Background planes around a detection box. The paper's object step (Sec. III-E)
// keeps the box depths near their robust mean, but the floor under a table or a
// chair and the wall just behind it lie at that same depth. Those surfaces do
// not stop at the box edge: planes fitted to the depth in a ring around the box
// and found again inside it are background, not object.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace sgslam {

struct Plane {
  Eigen::Vector3f normal = Eigen::Vector3f::UnitZ();  // unit
  float offset = 0;                                   // normal . p + offset = 0
  float Distance(const Eigen::Vector3f& p) const { return std::abs(normal.dot(p) + offset); }
};

struct PlaneFitOptions {
  int max_planes = 2;          // floor and one wall is the common case
  double min_share = 0.12;     // of the ring points, for a plane to count (low: a wall beside an
                               // object in a corner holds little of the ring)
  int min_points = 30;         // ring points on a plane, at least
  float tolerance = 0.03f;     // m, distance from a plane counted as on it
  int iterations = 100;        // RANSAC draws per plane
};

// Inlier test shared by the fit and its users. One tolerance for all points of a
// box (the caller scales it with the box's depth): a per-point tolerance growing
// with depth lets tilted planes win RANSAC by hugging the far points.
inline bool OnPlane(const Plane& plane, const Eigen::Vector3f& p, const PlaneFitOptions& options) {
  return plane.Distance(p) <= options.tolerance;
}

// Up to max_planes planes, largest first, each supported by enough of `points`
// (RANSAC on 3-point samples, refined by least squares on its inliers). The
// draws come from a fixed seed: the same input gives the same planes.
std::vector<Plane> FitPlanes(const std::vector<Eigen::Vector3f>& points, const PlaneFitOptions& options);

}  // namespace sgslam
