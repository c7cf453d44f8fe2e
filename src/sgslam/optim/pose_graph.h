// Pose-graph optimisation with the semantics of ORB-SLAM2's
// Optimizer::OptimizeEssentialGraph for RGB-D (SE(3), no scale): keyframe poses
// joined by relative-pose edges, Levenberg-Marquardt for `iterations`, fixed
// nodes held constant.
//
// Edge (i, j) measures T_i_j = T_ci_cj = T_ci_w * T_cj_w^-1: ordinary edges take it
// from the poses before the loop correction, loop edges from the verified loop
// transform. Residual r = Log(T_i_j^-1 * T_ci_w * T_cj_w^-1) (6-vector [rho; phi]
// of common/se3.h), weighted by sqrt(weight) and, on the rho rows, by
// sqrt(translation_weight); ORB-SLAM2 uses identity information, both weights 1.
// Poses use SE3LeftManifold (T <- Exp(delta) T); Jacobians are analytic.
//
// Map-agnostic: the caller copies keyframe poses and edges in and moves each map
// point with its reference keyframe's correction T_c_w_new^-1 * T_c_w_old.
// Deterministic (one thread, fixed order). Pure function, safe from any thread.
#pragma once

#include <ceres/sized_cost_function.h>

#include <cstdint>
#include <vector>

#include "sgslam/common/se3.h"

namespace sgslam::optim {

struct PoseGraphNode {
  std::uint64_t id = 0;  // unique (edges name a repeated id's first node)
  SE3 T_c_w;             // world -> camera
  bool fixed = false;
};

struct PoseGraphEdge {
  std::uint64_t id_i = 0, id_j = 0;
  SE3 T_i_j;          // measured T_ci_cj
  double weight = 1;  // information scale, >= 0
};

struct PoseGraphProblem {
  std::vector<PoseGraphNode> nodes;
  std::vector<PoseGraphEdge> edges;
};

struct PoseGraphOptions {
  int iterations = 20;            // LM iterations at most (ORB-SLAM2: 20)
  double translation_weight = 1;  // information of the rho rows relative to phi [rad^2 / m^2]
};

struct PoseGraphResult {
  std::vector<SE3> T_c_w;   // one per node, in input order
  int invalid_edges = 0;    // naming an unknown node or one node twice: left out
  int iterations = 0;       // LM iterations run
  double initial_cost = 0;  // Ceres cost, 1/2 sum |r|^2; 0 when nothing was free to move
  double final_cost = 0;
  bool success = true;  // false when Ceres found no usable solution (poses unchanged)
};

// Fixed nodes and nodes without a valid edge keep their pose exactly. With no
// fixed node the one with the smallest id is held (the gauge).
PoseGraphResult OptimizePoseGraph(const PoseGraphProblem& problem, const PoseGraphOptions& options = {});

// One edge as a Ceres cost on the two 7-double pose blocks of se3_manifold.h.
// sqrt_info scales the residual rows; returns ambient Jacobians whose product
// with SE3LeftManifold::PlusJacobian is the exact tangent Jacobian.
class RelativePoseCost final : public ceres::SizedCostFunction<6, 7, 7> {
 public:
  RelativePoseCost(const SE3& T_i_j, const Vector6d& sqrt_info) : T_j_i_meas_(T_i_j.Inverse()), sqrt_info_(sqrt_info) {}
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  SE3 T_j_i_meas_;
  Vector6d sqrt_info_;
};

}  // namespace sgslam::optim
