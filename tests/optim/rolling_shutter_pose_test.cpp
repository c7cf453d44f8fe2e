// Pose and angular velocity of a rolling-shutter frame: synthetic matches seen by
// a camera turning during its readout, corrected with a wrong predicted velocity.
#include "sgslam/optim/rolling_shutter_pose.h"

#include <gtest/gtest.h>

#include <random>

#include "sgslam/camera/camera.h"
#include "sgslam/camera/rolling_shutter.h"

namespace sgslam::optim {
namespace {

constexpr double kReadout = 0.03;

struct Frame {
  SE3 T_c_w;
  std::vector<PoseObservation> obs;  // keypoints corrected with `predicted`
  std::vector<double> row_time;
};

// n world points seen by a camera at T_c_w (middle row) turning at w; the
// keypoints are corrected with `predicted` as the tracker would before the fit.
Frame MakeFrame(const Camera& cam, const Eigen::Vector3d& w, const Eigen::Vector3d& predicted, double noise_px,
                unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(0, 1);
  std::normal_distribution<double> N(0, 1);
  Frame f;
  f.T_c_w = SE3(so3::Exp(Eigen::Vector3d(0.2, -0.4, 0.1)), Eigen::Vector3d(0.3, -0.1, 0.8));
  const SE3 T_w_c = f.T_c_w.Inverse();
  for (int i = 0; i < 300; ++i) {
    const Eigen::Vector3d p_c = cam.Unproject(20 + 600 * U(rng), 20 + 440 * U(rng), 0.8 + 4 * U(rng));
    Eigen::Vector3d p = p_c;
    double s = 0;
    for (int it = 0; it < 20; ++it) {
      s = RowTimeOffset(cam.Project(p).y(), cam.height(), kReadout);
      p = so3::Exp(-w * s) * p_c;
    }
    const Eigen::Vector2d uv = cam.Project(p) + noise_px * Eigen::Vector2d(N(rng), N(rng));
    std::vector<cv::KeyPoint> raw = {cv::KeyPoint(static_cast<float>(uv.x()), static_cast<float>(uv.y()), 31)};
    std::vector<cv::KeyPoint> key = raw;
    std::vector<float> depth = {static_cast<float>(p.z())};
    CorrectRollingShutter(cam, raw, Eigen::Vector3d::Zero(), predicted, key, depth);
    PoseObservation o;
    o.p_w = T_w_c * p_c;
    o.uv = {key[0].pt.x, key[0].pt.y};
    o.u_right = key[0].pt.x - cam.baseline_fx() / depth[0];
    f.obs.push_back(o);
    f.row_time.push_back(s);
  }
  return f;
}

Camera PinholeCamera() {
  CameraConfig c;
  c.k1 = c.k2 = c.p1 = c.p2 = c.k3 = 0;
  c.readout = kReadout;
  return Camera(c);
}

Intrinsics IntrinsicsOf(const Camera& cam) { return {cam.fx(), cam.fy(), cam.cx(), cam.cy(), cam.baseline_fx()}; }

double AngleDeg(const SE3& a, const SE3& b) { return so3::Log((a * b.Inverse()).quaternion()).norm() * 180 / 3.14159265358979; }

TEST(RollingShutterPose, FitsTheVelocityThePredictionMissed) {
  const Camera cam = PinholeCamera();
  const Eigen::Vector3d w(0.5, -1.6, 0.3), predicted(0.1, -0.8, 0.0);
  const Frame f = MakeFrame(cam, w, predicted, 0.5, 1);
  const SE3 start(f.T_c_w.quaternion() * so3::Exp(Eigen::Vector3d(0.01, -0.01, 0.005)),
                  f.T_c_w.translation() + Eigen::Vector3d(0.01, 0.0, -0.01));
  RollingShutterPoseOptions options;
  options.prior_sigma = 10;  // the data alone
  const auto r = OptimizePoseAndAngularVelocity(start, f.obs, f.row_time, IntrinsicsOf(cam), options);
  ASSERT_TRUE(r.ok);
  EXPECT_LT((predicted + r.delta - w).norm(), 0.05) << (predicted + r.delta).transpose();
  EXPECT_LT((r.T_c_w.translation() - f.T_c_w.translation()).norm(), 0.003);
  EXPECT_LT(AngleDeg(r.T_c_w, f.T_c_w), 0.05);
}

TEST(RollingShutterPose, TheRightPredictionStays) {
  const Camera cam = PinholeCamera();
  const Eigen::Vector3d w(-0.7, 1.0, -0.2);
  const Frame f = MakeFrame(cam, w, w, 0.5, 2);
  const auto r = OptimizePoseAndAngularVelocity(f.T_c_w, f.obs, f.row_time, IntrinsicsOf(cam));
  ASSERT_TRUE(r.ok);
  EXPECT_LT(r.delta.norm(), 0.05);
  EXPECT_LT((r.T_c_w.translation() - f.T_c_w.translation()).norm(), 0.003);
}

TEST(RollingShutterPose, AStrongPriorHoldsTheVelocityAtThePrediction) {
  const Camera cam = PinholeCamera();
  const Eigen::Vector3d w(0.0, -1.5, 0.0), predicted(0.0, -0.5, 0.0);
  const Frame f = MakeFrame(cam, w, predicted, 0.5, 3);
  RollingShutterPoseOptions weak, strong;
  weak.prior_sigma = 10;
  strong.prior_sigma = 0.001;
  const auto a = OptimizePoseAndAngularVelocity(f.T_c_w, f.obs, f.row_time, IntrinsicsOf(cam), weak);
  const auto b = OptimizePoseAndAngularVelocity(f.T_c_w, f.obs, f.row_time, IntrinsicsOf(cam), strong);
  ASSERT_TRUE(a.ok && b.ok);
  EXPECT_GT(a.delta.norm(), 0.9);
  EXPECT_LT(b.delta.norm(), 0.1);
}

TEST(RollingShutterPose, TooFewMatchesLeaveThePoseAlone) {
  const Camera cam = PinholeCamera();
  Frame f = MakeFrame(cam, Eigen::Vector3d(0, 1, 0), Eigen::Vector3d::Zero(), 0.5, 4);
  f.obs.resize(10);
  f.row_time.resize(10);
  const auto r = OptimizePoseAndAngularVelocity(f.T_c_w, f.obs, f.row_time, IntrinsicsOf(cam));
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.delta, Eigen::Vector3d::Zero());
  f.row_time.pop_back();
  EXPECT_THROW(OptimizePoseAndAngularVelocity(f.T_c_w, f.obs, f.row_time, IntrinsicsOf(cam)), std::invalid_argument);
}

}  // namespace
}  // namespace sgslam::optim
