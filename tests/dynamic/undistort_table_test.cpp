// The interpolated undistortion of the flow pairs against Camera::Undistort.
#include <gtest/gtest.h>

#include <random>

#include "sgslam/camera/camera.h"
#include "sgslam/dynamic/undistort_table.h"

namespace sgslam::dynamic {
namespace {

TEST(UndistortTable, MatchesTheExactUndistortionOnTheFr1Lens) {
  CameraConfig c;
  c.width = 640, c.height = 480;
  c.fx = 517.3, c.fy = 516.5, c.cx = 318.6, c.cy = 255.3;
  c.k1 = 0.2624, c.k2 = -0.9531, c.p1 = -0.0054, c.p2 = 0.0026, c.k3 = 1.1633;
  const Camera camera(c);
  const UndistortTable table({640, 480}, [&](std::vector<cv::Point2f>& p) { camera.Undistort(p); });
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> x(0, 639.999f), y(0, 479.999f);
  std::vector<cv::Point2f> raw;
  for (int i = 0; i < 5000; ++i) raw.emplace_back(x(rng), y(rng));
  raw.emplace_back(0.f, 0.f);
  raw.emplace_back(639.9f, 479.9f);
  raw.emplace_back(-3.f, 20.f);    // outside: exact fallback
  raw.emplace_back(650.f, 490.f);
  std::vector<cv::Point2f> exact = raw, fast = raw;
  camera.Undistort(exact);
  table.Apply(fast);
  double worst = 0;
  for (size_t i = 0; i < raw.size(); ++i) worst = std::max(worst, cv::norm(exact[i] - fast[i]));
  std::printf("max interpolation error %.5f px\n", worst);
  EXPECT_LT(worst, 0.005);
  EXPECT_EQ(fast[fast.size() - 1], exact[exact.size() - 1]);
  EXPECT_EQ(fast[fast.size() - 2], exact[exact.size() - 2]);
}

TEST(UndistortTable, IdentityStaysTheIdentity) {
  const UndistortTable table({64, 48}, [](std::vector<cv::Point2f>&) {}, 4);
  std::vector<cv::Point2f> p = {{0.f, 0.f}, {10.3f, 7.7f}, {63.f, 47.f}};
  const std::vector<cv::Point2f> before = p;
  table.Apply(p);
  for (size_t i = 0; i < p.size(); ++i) EXPECT_NEAR(cv::norm(p[i] - before[i]), 0.0, 1e-4);
}

}  // namespace
}  // namespace sgslam::dynamic
