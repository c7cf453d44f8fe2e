#include "sgslam/camera/camera.h"
#include "sgslam/geometry/epipolar.h"
#include "sgslam/geometry/triangulation.h"

#include <gtest/gtest.h>

#include <random>

namespace sgslam::geometry {
namespace {

TEST(Triangulation, RecoversPointsFromTwoViews) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  const Camera cam(CameraConfig{});
  for (int k = 0; k < 100; ++k) {
    const SE3 T_1w = SE3::Exp((Vector6d() << u(rng), u(rng), u(rng), 0.2 * u(rng), 0.2 * u(rng), 0.2 * u(rng)).finished());
    const SE3 T_21 = SE3::Exp((Vector6d() << 0.3 + 0.1 * u(rng), 0.1 * u(rng), 0.1 * u(rng), 0.05 * u(rng), 0.05 * u(rng), 0.05 * u(rng)).finished());
    const SE3 T_2w = T_21 * T_1w;
    const Eigen::Vector3d p_c1(u(rng), u(rng), 2.0 + u(rng));
    const Eigen::Vector3d p_w = T_1w.Inverse() * p_c1;
    const Eigen::Vector3d p_c2 = T_2w * p_w;
    const auto t = Triangulate(p_c1 / p_c1.z(), p_c2 / p_c2.z(), T_1w, T_2w);
    ASSERT_TRUE(t);
    EXPECT_LT((*t - p_w).norm(), 1e-8);
    // The fundamental matrix maps the pixel pair onto each other's epipolar lines.
    const Eigen::Vector2d x1 = cam.Project(p_c1), x2 = cam.Project(p_c2);
    const Eigen::Matrix3d F = FundamentalMatrix(T_2w * T_1w.Inverse(), {cam.fx(), cam.fy(), cam.cx(), cam.cy()});
    const Eigen::Vector3d line = F * x1.homogeneous();
    EXPECT_LT(std::abs(x2.homogeneous().dot(line)) / line.head<2>().norm(), 1e-6);
  }
}

TEST(Triangulation, ParallelRaysGiveNoPoint) {
  const SE3 T_1w;
  const SE3 T_2w(Eigen::Quaterniond::Identity(), Eigen::Vector3d(-0.5, 0, 0));
  const Eigen::Vector3d ray(0.1, 0.2, 1.0);
  const auto t = Triangulate(ray, ray, T_1w, T_2w);  // a point at infinity
  EXPECT_TRUE(!t || t->norm() > 1e6);
}

}  // namespace
}  // namespace sgslam::geometry
