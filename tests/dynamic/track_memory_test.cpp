// The multi-frame check (track_memory.h) on synthetic truth: a patch of points that
// moves too slowly for any two-frame test (about 1 px a frame, below the 3 px
// tolerance) is caught after a few frames, while static points with keypoint and
// motion noise are not.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "sgslam/dynamic/track_memory.h"

namespace sgslam::dynamic {
namespace {

constexpr double kFx = 517.3, kFy = 516.5, kCx = 318.6, kCy = 255.3;

Eigen::Vector2d Project(const Eigen::Vector3d& X) {
  return {kFx * X.x() / X.z() + kCx, kFy * X.y() / X.z() + kCy};
}

SE3 CameraPose(int k) {  // T_c_w: a hand-held-like sway, up to 0.25 deg and 4 mm a frame
  Vector6d xi;
  xi << 0.003, -0.001, 0.002, 0.003, 0.002, -0.001;
  return SE3::Exp(5.0 * std::sin(0.25 * static_cast<double>(k)) * xi);
}

struct Outcome {
  int movers = 0, movers_caught = 0, statics = 0, statics_flagged = 0;
  int flagged_at_frame_1 = 0;
  double mover_step_px = 0;  // median two-frame image motion of a mover beyond the camera's
};

Outcome Simulate(int frames, double speed, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> pixel_noise(0.0, 0.3);   // px, keypoint localisation
  std::normal_distribution<double> motion_noise(0.0, 4e-4);  // rad and m, frame-to-frame motion error
  std::uniform_real_distribution<double> depth(1.5, 3.5);
  // A grid of points seen by camera 0; a 4x5 patch in the middle moves sideways.
  std::vector<Eigen::Vector3d> X_w;
  std::vector<bool> mover;
  for (int gy = 0; gy < 14; ++gy) {
    for (int gx = 0; gx < 19; ++gx) {
      const double u = 40 + 30.0 * gx, v = 40 + 30.0 * gy, z = depth(rng);
      X_w.push_back(CameraPose(0).Inverse() * Eigen::Vector3d((u - kCx) / kFx * z, (v - kCy) / kFy * z, z));
      mover.push_back(gx >= 8 && gx < 12 && gy >= 5 && gy < 10);
    }
  }
  const Eigen::Vector3d velocity(speed, 0, 0);  // m a frame, world
  DynamicConfig config;
  TrackMemory memory;
  std::vector<cv::Point2f> prev_uv;
  Outcome run;
  std::vector<double> steps;
  for (int k = 0; k < frames; ++k) {
    const SE3 T_c_w = CameraPose(k);
    cv::Mat depth_image(480, 640, CV_32F, cv::Scalar(0));
    std::vector<cv::KeyPoint> keys;
    std::vector<cv::Point2f> cur_un;
    FlowPairs flow;
    for (std::size_t i = 0; i < X_w.size(); ++i) {
      const Eigen::Vector3d step = mover[i] ? Eigen::Vector3d(static_cast<double>(k) * velocity) : Eigen::Vector3d::Zero();
      const Eigen::Vector3d X_c = T_c_w * (X_w[i] + step);
      const Eigen::Vector2d uv = Project(X_c) + Eigen::Vector2d(pixel_noise(rng), pixel_noise(rng));
      const cv::Point2f p(static_cast<float>(uv.x()), static_cast<float>(uv.y()));
      keys.emplace_back(p, 31.0f);
      cur_un.push_back(p);
      depth_image(cv::Rect(cvRound(p.x) - 1, cvRound(p.y) - 1, 3, 3)).setTo(cv::Scalar(X_c.z()));
      if (k > 0) {
        flow.prev.push_back(prev_uv[i] + cv::Point2f(0.2f, -0.2f));  // LK lands near, not on, the old keypoint
        flow.status.push_back(PairStatus::kOk);
        if (mover[i]) {
          const Eigen::Vector2d still = Project(T_c_w * (X_w[i] + static_cast<double>(k - 1) * velocity));
          steps.push_back((Project(X_c) - still).norm());
        }
      }
    }
    std::optional<SE3> T_cur_prev;
    if (k > 0) {
      Vector6d e;
      for (int j = 0; j < 6; ++j) e[j] = motion_noise(rng);
      T_cur_prev = SE3::Exp(e) * T_c_w * CameraPose(k - 1).Inverse();
    }
    const auto verdicts = memory.Update(keys, cur_un, flow, flow.prev, depth_image, 1.0, Pinhole{kFx, kFy, kCx, kCy}, T_cur_prev, config);
    for (std::size_t i = 0; i < verdicts.size(); ++i) {
      if (k == 1) run.flagged_at_frame_1 += verdicts[i].moving;
      if (k != frames - 1) continue;
      if (mover[i]) ++run.movers, run.movers_caught += verdicts[i].moving;
      else ++run.statics, run.statics_flagged += verdicts[i].moving;
    }
    prev_uv.clear();
    for (const auto& key : keys) prev_uv.push_back(key.pt);
  }
  std::sort(steps.begin(), steps.end());
  run.mover_step_px = steps[steps.size() / 2];
  return run;
}

TEST(TrackMemory, CatchesASlowMoverThatStaticNoiseDoesNot) {
  const Outcome run = Simulate(12, 0.006, 7);  // 6 mm a frame at 1.5-3.5 m
  EXPECT_LT(run.mover_step_px, 2.0);       // under any two-frame tolerance on real frames
  EXPECT_EQ(run.flagged_at_frame_1, 0);    // too young to be judged
  ASSERT_EQ(run.movers, 20);
  EXPECT_GE(run.movers_caught, 18);
  EXPECT_LE(run.statics_flagged, run.statics / 50);  // <= 2 %
}

TEST(TrackMemory, StaticSceneStaysStaticOverManyFrames) {
  const Outcome run = Simulate(40, 0.0, 11);  // re-anchoring keeps the chained motion error small
  EXPECT_EQ(run.movers_caught, 0);
  EXPECT_LE(run.statics_flagged, run.statics / 50);
}

TEST(TrackMemory, RestartsWithoutMotion) {
  TrackMemory memory;
  DynamicConfig config;
  const std::vector<cv::KeyPoint> keys = {cv::KeyPoint(cv::Point2f(100, 100), 31.0f)};
  const std::vector<cv::Point2f> un = {cv::Point2f(100, 100)};
  cv::Mat depth(480, 640, CV_32F, cv::Scalar(2.0));
  FlowPairs flow;
  flow.prev = un;
  flow.status = {PairStatus::kOk};
  memory.Update(keys, un, flow, un, depth, 1.0, Pinhole{kFx, kFy, kCx, kCy}, std::nullopt, config);
  const auto v = memory.Update(keys, un, flow, un, depth, 1.0, Pinhole{kFx, kFy, kCx, kCy}, std::nullopt, config);
  EXPECT_EQ(v[0].age, 0);  // a fresh anchor each time
  EXPECT_FALSE(v[0].moving);
}

}  // namespace
}  // namespace sgslam::dynamic
