// Trusted map points (tracking/trusted_pose.h) on synthetic ground truth: a rigid
// group of fresh, precise matches on a moving object against fewer, noisier static
// ones, as on dyn_dev's box; the optimiser's classify_only / start_excluded flags;
// and how a map point earns trust.
#include "sgslam/tracking/trusted_pose.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "sgslam/camera/camera.h"
#include "sgslam/features/pyramid.h"
#include "sgslam/map/keyframe.h"
#include "sgslam/map/map_point.h"

namespace sgslam {
namespace {

const optim::Intrinsics kK{525.0, 525.0, 319.5, 239.5, 40.0};
constexpr double kPi = 3.14159265358979323846;

struct Scene {
  SE3 T_c_w;                              // the true camera pose
  std::vector<optim::PoseObservation> obs;
  std::vector<bool> trusted, moving, junk;  // junk: a random pixel (a wrong match)
};

// Static points seen with static_sigma px noise and 40 % wrong matches (a blurred real view);
// `movers` points on an object 1-2 m away that moved 8 cm since it was mapped,
// seen with 0.3 px noise (sharp, and mapped a frame ago: they agree with each
// other). The first `trusted_static` static points are trusted, no mover is.
Scene MakeScene(int statics, int movers, int trusted_static, unsigned seed, double static_sigma = 2.0) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(0, 1);
  std::normal_distribution<double> N(0, 1);
  Scene s;
  s.T_c_w = SE3(so3::Exp(Eigen::Vector3d(0.1, -0.2, 0.05)), Eigen::Vector3d(0.3, -0.1, 0.5));
  const SE3 T_w_c = s.T_c_w.Inverse();
  const Eigen::Vector3d object_motion_c(0.06, 0.0, -0.05);  // camera frame, m
  for (int i = 0; i < statics + movers; ++i) {
    const bool mover = i >= statics;
    const double u = mover ? 250 + 140 * U(rng) : 640 * U(rng);
    const double v = mover ? 180 + 140 * U(rng) : 480 * U(rng);
    const double z = mover ? 1.0 + U(rng) : 0.8 + 4.2 * U(rng);
    const Eigen::Vector3d seen_c((u - kK.cx) * z / kK.fx, (v - kK.cy) * z / kK.fy, z);
    // A mover's map point is where the object was; the view shows where it is.
    const Eigen::Vector3d mapped_c = mover ? Eigen::Vector3d(seen_c - object_motion_c) : seen_c;
    const double sigma = mover ? 0.3 : static_sigma;
    const bool junk = !mover && U(rng) < 0.4;
    optim::PoseObservation o;
    o.p_w = T_w_c * mapped_c;
    o.uv = junk ? Eigen::Vector2d(640 * U(rng), 480 * U(rng)) : Eigen::Vector2d(u + sigma * N(rng), v + sigma * N(rng));
    o.u_right = o.uv.x() - kK.bf / (junk ? 0.8 + 4.2 * U(rng) : z + 0.01 * z * N(rng));
    s.obs.push_back(o);
    s.trusted.push_back(!mover && i < trusted_static);
    s.moving.push_back(mover);
    s.junk.push_back(junk);
  }
  return s;
}

double TranslationError(const SE3& a, const SE3& b) { return (a * b.Inverse()).translation().norm(); }
double RotationErrorDeg(const SE3& a, const SE3& b) {
  return so3::Log((a * b.Inverse()).quaternion()).norm() * 180 / kPi;
}

TEST(TrustedPose, FreshMoversCannotPullThePoseAwayFromTrustedPoints) {
  const Scene s = MakeScene(/*statics=*/100, /*movers=*/140, /*trusted_static=*/30, 7);
  const SE3 start = SE3(so3::Exp(Eigen::Vector3d(0.01, 0.0, -0.01)), Eigen::Vector3d(0.02, 0.01, 0.0)) * s.T_c_w;

  // Every match sets the pose (ORB-SLAM2): the precise rigid group wins.
  const auto plain = optim::OptimizePose(start, s.obs, kK);
  EXPECT_GT(TranslationError(plain.T_c_w, s.T_c_w), 0.03);

  bool trusted_start = false;
  const TrustOptions options{0.3, 2, 20};
  const auto r = OptimizePoseTrusted(start, s.obs, s.trusted, kK, options, &trusted_start);
  EXPECT_TRUE(trusted_start);
  EXPECT_LT(TranslationError(r.T_c_w, s.T_c_w), 0.01);
  EXPECT_LT(RotationErrorDeg(r.T_c_w, s.T_c_w), 0.3);
  // What the true pose classifies as inliers: the most the fit can keep.
  std::vector<optim::PoseObservation> judged = s.obs;
  for (auto& o : judged) o.classify_only = true;
  const auto truth = optim::OptimizePose(s.T_c_w, judged, kK);
  int movers = 0, movers_out = 0, fresh_static = 0, fresh_static_in = 0;
  for (std::size_t k = 0; k < s.obs.size(); ++k) {
    if (s.moving[k]) {
      ++movers;
      movers_out += r.inlier[k] ? 0 : 1;
    } else if (!s.trusted[k] && truth.inlier[k]) {
      ++fresh_static;
      fresh_static_in += r.inlier[k] ? 1 : 0;
    }
  }
  EXPECT_GE(movers_out, movers * 95 / 100);
  // Untrusted static points that agree join the fit.
  EXPECT_GE(fresh_static_in, fresh_static * 80 / 100) << fresh_static_in << " of " << fresh_static;
}

TEST(TrustedPose, TooFewTrustedMatchesFitEveryMatchAsBefore) {
  const Scene s = MakeScene(100, 140, /*trusted_static=*/10, 8);
  int trusted = 0;
  for (bool t : s.trusted) trusted += t ? 1 : 0;
  ASSERT_LT(trusted, 20);
  bool trusted_start = true;
  const auto r = OptimizePoseTrusted(s.T_c_w, s.obs, s.trusted, kK, TrustOptions{0.3, 2, 20}, &trusted_start);
  const auto plain = optim::OptimizePose(s.T_c_w, s.obs, kK);
  EXPECT_FALSE(trusted_start);
  EXPECT_EQ(r.T_c_w.translation(), plain.T_c_w.translation());
  EXPECT_EQ(r.inlier, plain.inlier);
  // trust_delay 0 switches it off whatever is trusted.
  const auto off = OptimizePoseTrusted(s.T_c_w, s.obs, std::vector<bool>(s.obs.size(), true), kK, TrustOptions{0, 2, 20});
  EXPECT_EQ(off.T_c_w.translation(), plain.T_c_w.translation());
}

TEST(PoseOptimizerFlags, ClassifyOnlyObservationsAreJudgedButNeverFitted) {
  Scene s = MakeScene(120, 0, 0, 9, /*static_sigma=*/1.0);
  std::vector<optim::PoseObservation> with = s.obs, without;
  for (std::size_t k = 0; k < with.size(); ++k) {
    if (k % 3 == 0) {
      with[k].classify_only = true;
    } else {
      without.push_back(with[k]);
    }
  }
  const auto a = optim::OptimizePose(s.T_c_w, with, kK);
  const auto b = optim::OptimizePose(s.T_c_w, without, kK);
  EXPECT_EQ(a.T_c_w.translation(), b.T_c_w.translation());
  // The classify-only ones are classified at the pose like the rest.
  int judged_in = 0, good = 0;
  for (std::size_t k = 0; k < with.size(); k += 3) {
    if (s.junk[k]) continue;
    ++good;
    judged_in += a.inlier[k] ? 1 : 0;
  }
  EXPECT_GE(judged_in, good * 7 / 10);
}

TEST(PoseOptimizerFlags, StartExcludedObservationsComeBackWhenTheyFit) {
  Scene s = MakeScene(120, 0, 0, 10, /*static_sigma=*/1.0);
  int excluded_good = 0;
  for (std::size_t k = 0; k < s.obs.size(); k += 2) {
    s.obs[k].start_excluded = true;
    excluded_good += s.junk[k] ? 0 : 1;
  }
  const auto r = optim::OptimizePose(s.T_c_w, s.obs, kK);
  int back = 0;
  for (std::size_t k = 0; k < s.obs.size(); k += 2) back += !s.junk[k] && r.inlier[k] ? 1 : 0;
  EXPECT_GE(back, excluded_good * 7 / 10);
  EXPECT_LT(TranslationError(r.T_c_w, s.T_c_w), 0.02);
}

// A map point made by a keyframe at time t0, matched in frames after it.
class TrustUpdate : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto camera = std::make_shared<Camera>(CameraConfig{});
    const auto scale = std::make_shared<ScaleLevels>(features::MakeScaleLevels(1.2, 8));
    std::vector<cv::KeyPoint> keys = {cv::KeyPoint(100.f, 100.f, 31.f)};
    cv::Mat desc(1, 32, CV_8U, cv::Scalar(0));
    cv::Mat depth(480, 640, CV_16UC1, cv::Scalar(10000));
    auto features = MakeFeatures(keys, desc, depth, camera, scale);
    kf_ = std::make_shared<KeyFrame>(0, 0, FromSeconds(10.0), features, SE3());
    point_ = std::make_shared<MapPoint>(0, Eigen::Vector3d(0, 0, 2), kf_);
  }
  void Match(double t, bool inlier) {
    Frame f;
    f.t = FromSeconds(t);
    f.map_points = {point_};
    f.outlier = {static_cast<std::uint8_t>(inlier ? 0 : 1)};
    UpdateTrust(f, options_);
  }
  const TrustOptions options_{0.3, 2, 20};
  std::shared_ptr<KeyFrame> kf_;
  std::shared_ptr<MapPoint> point_;
};

TEST_F(TrustUpdate, TrustIsEarnedByInlierMatchesAfterTheDelay) {
  EXPECT_EQ(point_->created_t, FromSeconds(10.0));
  Match(10.1, true);  // too young: a mover still sits where it was mapped
  Match(10.2, true);
  EXPECT_FALSE(point_->track.trusted);
  Match(10.4, false);  // an outlier earns nothing
  EXPECT_FALSE(point_->track.trusted);
  Match(10.5, true);
  EXPECT_FALSE(point_->track.trusted);
  Match(10.6, true);
  EXPECT_TRUE(point_->track.trusted);
}

TEST_F(TrustUpdate, OffWhenTheDelayIsZeroAndTheFirstKeyFrameIsTrusted) {
  Frame f;
  f.t = FromSeconds(20.0);
  f.map_points = {point_};
  f.outlier = {0};
  for (int i = 0; i < 5; ++i) UpdateTrust(f, TrustOptions{0.0, 2, 20});
  EXPECT_FALSE(point_->track.trusted);
  TrustAll({point_, nullptr});
  EXPECT_TRUE(point_->track.trusted);
  EXPECT_EQ(CountTrustedInliers(f), 1);
}

}  // namespace
}  // namespace sgslam
