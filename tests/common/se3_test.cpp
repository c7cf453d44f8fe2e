#include "sgslam/common/se3.h"

#include <gtest/gtest.h>

#include <random>

namespace sgslam {
namespace {

Vector6d RandomTangent(std::mt19937& rng, double scale) {
  std::normal_distribution<double> n(0.0, scale);
  Vector6d xi;
  for (int i = 0; i < 6; ++i) xi[i] = n(rng);
  return xi;
}

TEST(SE3, ExpLogRoundTrip) {
  std::mt19937 rng(1);
  for (double scale : {1e-9, 1e-5, 0.1, 1.0}) {
    for (int i = 0; i < 200; ++i) {
      Vector6d xi = RandomTangent(rng, scale);
      if (xi.tail<3>().norm() > 3.0) xi.tail<3>() *= 3.0 / xi.tail<3>().norm();  // stay below pi
      const Vector6d back = SE3::Exp(xi).Log();
      EXPECT_LT((back - xi).norm(), 1e-9 * std::max(1.0, xi.norm())) << "scale " << scale;
    }
  }
}

TEST(SE3, ExpMatchesMatrixExponential) {
  // Closed form against the series of the 4x4 twist matrix.
  std::mt19937 rng(2);
  for (int i = 0; i < 50; ++i) {
    const Vector6d xi = RandomTangent(rng, 0.7);
    Eigen::Matrix4d X = Eigen::Matrix4d::Zero();
    X.topLeftCorner<3, 3>() = Hat(xi.tail<3>());
    X.topRightCorner<3, 1>() = xi.head<3>();
    Eigen::Matrix4d term = Eigen::Matrix4d::Identity(), sum = Eigen::Matrix4d::Identity();
    for (int k = 1; k < 40; ++k) {
      term = term * X / k;
      sum += term;
    }
    EXPECT_LT((SE3::Exp(xi).matrix() - sum).norm(), 1e-10);
  }
}

TEST(SE3, CompositionInverseAndAction) {
  std::mt19937 rng(3);
  for (int i = 0; i < 100; ++i) {
    const SE3 a = SE3::Exp(RandomTangent(rng, 1.0));
    const SE3 b = SE3::Exp(RandomTangent(rng, 1.0));
    const Eigen::Vector3d p(0.3, -1.2, 2.5);
    EXPECT_LT(((a * b) * p - a * (b * p)).norm(), 1e-12);
    EXPECT_LT(((a * b).matrix() - a.matrix() * b.matrix()).norm(), 1e-12);
    EXPECT_LT((a.Inverse() * (a * p) - p).norm(), 1e-12);
  }
}

TEST(SO3, LogOfHalfTurnHasAnglePi) {
  const Eigen::Vector3d phi(0, 0, M_PI);
  EXPECT_NEAR(so3::Log(so3::Exp(phi)).norm(), M_PI, 1e-12);
  EXPECT_LT((so3::LeftJacobian(phi * 0.5) * so3::LeftJacobianInverse(phi * 0.5) - Eigen::Matrix3d::Identity()).norm(),
            1e-12);
}

}  // namespace
}  // namespace sgslam
