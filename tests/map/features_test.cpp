// The per-image feature data: undistortion, depth lookup, the virtual right
// coordinate and the rolling-shutter correction keeping them consistent.
#include "sgslam/map/features.h"

#include <gtest/gtest.h>

#include "sgslam/camera/rolling_shutter.h"

namespace sgslam {
namespace {

struct Scene {
  std::shared_ptr<const Camera> camera;
  std::shared_ptr<const ScaleLevels> scale = std::make_shared<ScaleLevels>(features::MakeScaleLevels(1.2, 8));
  std::vector<cv::KeyPoint> keys;
  cv::Mat depth = cv::Mat(480, 640, CV_16UC1, cv::Scalar(10000));  // 2 m
  cv::Mat descriptors;
};

Scene MakeScene(double readout) {
  Scene s;
  CameraConfig c;  // TUM fr1 intrinsics and distortion
  c.readout = readout;
  s.camera = std::make_shared<Camera>(c);
  for (int v = 30; v < 470; v += 40) {
    for (int u = 30; u < 630; u += 40) s.keys.emplace_back(static_cast<float>(u), static_cast<float>(v), 31.0f);
  }
  s.depth(cv::Rect(0, 0, 100, 100)).setTo(0);  // some keypoints without depth
  s.descriptors = cv::Mat::zeros(static_cast<int>(s.keys.size()), 32, CV_8U);
  return s;
}

void ExpectConsistent(const Features& f) {
  for (std::size_t i = 0; i < f.size(); ++i) {
    if (f.depth[i] > 0) {
      EXPECT_NEAR(f.u_right[i], f.keys_un[i].pt.x - f.camera->baseline_fx() / f.depth[i], 1e-3) << i;
    } else {
      EXPECT_LT(f.u_right[i], 0) << i;
    }
    // The grid finds every keypoint where its corrected position is.
    const auto near = f.InArea(f.keys_un[i].pt.x, f.keys_un[i].pt.y, 1.0);
    EXPECT_NE(std::find(near.begin(), near.end(), i), near.end()) << i;
  }
}

TEST(Features, TheRollingShutterCorrectionMovesKeypointsDepthAndRightCoordinate) {
  const Scene s = MakeScene(0.03);
  const Eigen::Vector3d w(0.4, -1.5, 0.2);
  const auto plain = MakeFeatures(s.keys, s.descriptors, s.depth, s.camera, s.scale);
  const auto corrected = MakeFeatures(s.keys, s.descriptors, s.depth, s.camera, s.scale, {}, {}, {}, w);
  EXPECT_EQ(plain->angular_velocity, Eigen::Vector3d::Zero());
  EXPECT_EQ(corrected->angular_velocity, w);
  ExpectConsistent(*corrected);
  double top = 0, bottom = 0;
  for (std::size_t i = 0; i < s.keys.size(); ++i) {
    const double shift = std::abs(corrected->keys_un[i].pt.x - plain->keys_un[i].pt.x);
    if (s.keys[i].pt.y < 60) top = std::max(top, shift);
    if (std::abs(s.keys[i].pt.y - 240) < 25) {
      EXPECT_LT(shift, 1.0) << "rows near the middle barely move";
    }
    if (s.keys[i].pt.y > 420) bottom = std::max(bottom, shift);
    EXPECT_EQ(corrected->depth[i] > 0, plain->depth[i] > 0);
  }
  EXPECT_GT(top, 4.0);  // 1.5 rad/s * 14 ms * 517 px
  EXPECT_GT(bottom, 4.0);

  // Correcting again with a better velocity equals correcting with it at once.
  const Eigen::Vector3d better(0.5, -1.2, 0.1);
  const auto direct = MakeFeatures(s.keys, s.descriptors, s.depth, s.camera, s.scale, {}, {}, {}, better);
  const auto again = WithRollingShutterCorrection(*corrected, better);
  ExpectConsistent(*again);
  for (std::size_t i = 0; i < s.keys.size(); ++i) {
    EXPECT_NEAR(again->keys_un[i].pt.x, direct->keys_un[i].pt.x, 1e-3);
    EXPECT_NEAR(again->keys_un[i].pt.y, direct->keys_un[i].pt.y, 1e-3);
    EXPECT_NEAR(again->depth[i], direct->depth[i], 1e-5);
  }
  EXPECT_EQ(corrected->angular_velocity, w) << "the original stays as it was";
}

TEST(Features, AGlobalShutterCameraIgnoresTheAngularVelocity) {
  const Scene s = MakeScene(0.0);
  const auto plain = MakeFeatures(s.keys, s.descriptors, s.depth, s.camera, s.scale);
  const auto turned = MakeFeatures(s.keys, s.descriptors, s.depth, s.camera, s.scale, {}, {}, {}, Eigen::Vector3d(1, 2, 3));
  for (std::size_t i = 0; i < s.keys.size(); ++i) {
    EXPECT_EQ(turned->keys_un[i].pt, plain->keys_un[i].pt);
    EXPECT_EQ(turned->depth[i], plain->depth[i]);
  }
  EXPECT_EQ(turned->angular_velocity, Eigen::Vector3d::Zero()) << "nothing was corrected";
  ExpectConsistent(*turned);
}

}  // namespace
}  // namespace sgslam
