// Rolling-shutter correction of keypoints: a synthetic camera turning during its
// readout, whose rows see the scene at different times.
#include "sgslam/camera/rolling_shutter.h"

#include <gtest/gtest.h>

#include <random>

#include "sgslam/camera/camera.h"
#include "sgslam/camera/presets.h"

namespace sgslam {
namespace {

CameraConfig PinholeWithReadout(double readout) {
  CameraConfig c;
  c.k1 = c.k2 = c.p1 = c.p2 = c.k3 = 0;  // raw rows = undistorted rows
  c.readout = readout;
  return c;
}

// Where a point p_c (middle-row camera) is seen by a camera turning at w: the row
// v whose exposure time s(v) satisfies v = row of Exp(-w s(v)) p_c.
struct Seen {
  cv::KeyPoint key;
  float depth;
};
Seen SeeWithRollingShutter(const Camera& cam, const Eigen::Vector3d& p_c, const Eigen::Vector3d& w) {
  Eigen::Vector3d p = p_c;
  for (int it = 0; it < 20; ++it) {
    const double v = cam.Project(p).y();
    p = so3::Exp(-w * RowTimeOffset(v, cam.height(), cam.config().readout)) * p_c;
  }
  const Eigen::Vector2d uv = cam.Project(p);
  return {cv::KeyPoint(static_cast<float>(uv.x()), static_cast<float>(uv.y()), 31), static_cast<float>(p.z())};
}

struct Scene {
  std::vector<Eigen::Vector3d> points;  // middle-row camera frame
  std::vector<cv::KeyPoint> raw;
  std::vector<float> depth;
};
Scene MakeScene(const Camera& cam, const Eigen::Vector3d& w, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(0, 1);
  Scene s;
  for (int i = 0; i < 200; ++i) {
    const double z = 0.8 + 4 * U(rng);
    const Eigen::Vector3d p = cam.Unproject(40 + 560 * U(rng), 30 + 420 * U(rng), z);
    const Seen seen = SeeWithRollingShutter(cam, p, w);
    s.points.push_back(p);
    s.raw.push_back(seen.key);
    s.depth.push_back(seen.depth);
  }
  return s;
}

TEST(RollingShutter, CorrectionBringsEveryRowToTheMiddleRowCamera) {
  const Camera cam(PinholeWithReadout(0.03));
  const Eigen::Vector3d w(0.6, -1.5, 0.4);  // rad/s, a fast turn of fr1_rpy
  Scene s = MakeScene(cam, w, 1);
  std::vector<cv::KeyPoint> keys = s.raw;
  double largest_shift = 0;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    largest_shift = std::max(largest_shift, (cam.Project(s.points[i]) - Eigen::Vector2d(keys[i].pt.x, keys[i].pt.y)).norm());
  }
  EXPECT_GT(largest_shift, 5.0) << "the turn should move the top and bottom rows by pixels";

  CorrectRollingShutter(cam, s.raw, Eigen::Vector3d::Zero(), w, keys, s.depth);
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const Eigen::Vector2d expected = cam.Project(s.points[i]);
    EXPECT_NEAR(keys[i].pt.x, expected.x(), 1e-3) << i;
    EXPECT_NEAR(keys[i].pt.y, expected.y(), 1e-3) << i;
    EXPECT_NEAR(s.depth[i], s.points[i].z(), 1e-5) << i;
  }
}

TEST(RollingShutter, CorrectingAgainWithABetterVelocityEqualsCorrectingOnce) {
  const Camera cam(PinholeWithReadout(0.03));
  const Eigen::Vector3d w(-0.8, 1.1, 0.2), guess(-0.2, 0.5, 0.0);
  const Scene s = MakeScene(cam, w, 2);
  std::vector<cv::KeyPoint> once = s.raw, twice = s.raw;
  std::vector<float> depth_once = s.depth, depth_twice = s.depth;
  // Points without depth are corrected as bearings.
  depth_once[3] = depth_twice[3] = -1;
  CorrectRollingShutter(cam, s.raw, Eigen::Vector3d::Zero(), w, once, depth_once);
  CorrectRollingShutter(cam, s.raw, Eigen::Vector3d::Zero(), guess, twice, depth_twice);
  CorrectRollingShutter(cam, s.raw, guess, w, twice, depth_twice);
  for (std::size_t i = 0; i < once.size(); ++i) {
    EXPECT_NEAR(once[i].pt.x, twice[i].pt.x, 1e-3) << i;
    EXPECT_NEAR(once[i].pt.y, twice[i].pt.y, 1e-3) << i;
    EXPECT_NEAR(depth_once[i], depth_twice[i], 1e-5) << i;
  }
  EXPECT_EQ(depth_once[3], -1.0f);
}

TEST(RollingShutter, AGlobalShutterLeavesKeypointsAlone) {
  const Camera cam(PinholeWithReadout(0.0));
  const Scene s = MakeScene(cam, Eigen::Vector3d::Zero(), 3);
  std::vector<cv::KeyPoint> keys = s.raw;
  std::vector<float> depth = s.depth;
  CorrectRollingShutter(cam, s.raw, Eigen::Vector3d::Zero(), Eigen::Vector3d(1, 2, 3), keys, depth);
  for (std::size_t i = 0; i < keys.size(); ++i) {
    EXPECT_EQ(keys[i].pt, s.raw[i].pt);
    EXPECT_EQ(depth[i], s.depth[i]);
  }
}

TEST(RollingShutter, AngularVelocityOfTheMotionModel) {
  const Eigen::Vector3d w(0.3, -1.2, 0.5);
  const double dt = 1.0 / 30;
  const SE3 T_w_last(so3::Exp(Eigen::Vector3d(0.1, 0.2, -0.3)), Eigen::Vector3d(0.5, 0.1, 1.0));
  const SE3 T_w_cur(T_w_last.quaternion() * so3::Exp(w * dt), Eigen::Vector3d(0.51, 0.1, 1.0));
  const auto got = AngularVelocity(T_w_cur.Inverse() * T_w_last, dt);
  ASSERT_TRUE(got.has_value());
  EXPECT_NEAR((*got - w).norm(), 0.0, 1e-9);
  EXPECT_FALSE(AngularVelocity(T_w_cur.Inverse() * T_w_last, 0.0).has_value());
  EXPECT_FALSE(AngularVelocity(T_w_cur.Inverse() * T_w_last, -dt).has_value());
}

TEST(RollingShutter, OnlyTheTumFr1PresetHasAReadoutTime) {
  EXPECT_DOUBLE_EQ(CameraPreset("tum_fr1")->readout, 0.03);
  for (const char* name : {"tum_fr2", "tum_fr3", "bonn"}) EXPECT_EQ(CameraPreset(name)->readout, 0.0) << name;
  EXPECT_EQ(CameraConfig{}.readout, 0.0) << "a camera nobody measured is taken as a global shutter";
}

}  // namespace
}  // namespace sgslam
