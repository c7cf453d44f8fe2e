// ATE / RPE on the real TUM fr1/rpy ground truth, perturbed in known ways and
// round-tripped through TUM files as a user's estimate would be.
#include <gtest/gtest.h>

#include "sgslam/common/error.h"
#include "sgslam/eval/evaluate.h"
#include "support/test_support.h"

namespace sgslam::eval {
namespace {

using test::TempDir;

Trajectory Every(const Trajectory& in, std::size_t step) {
  Trajectory out;
  for (std::size_t i = 0; i < in.size(); i += step) out.push_back(in[i]);
  return out;
}

TEST(EvalTumData, RigidlyMovedSubsampledCopyHasZeroError) {
  SGSLAM_REQUIRE_SHARED(dir, "data/tum_fr1_rpy");
  const std::filesystem::path gt_path = dir / "groundtruth.txt";
  const SE3 M(so3::Exp(Eigen::Vector3d(0.4, -1.1, 2.0)), Eigen::Vector3d(3.0, -2.0, 0.7));
  Trajectory est = Every(ReadTumTrajectory(gt_path), 3);  // 100 Hz -> ~30 Hz
  for (StampedPose& p : est) p.T_w_c = M * p.T_w_c;
  TempDir tmp;
  WriteTumTrajectory(tmp / "est.txt", est);
  const EvalReport r = EvaluateFiles(gt_path, tmp / "est.txt");
  EXPECT_EQ(r.ate.stats.count, est.size());
  EXPECT_LT(r.ate.stats.rmse, 1e-6);
  EXPECT_LT((r.ate.T_gt_est.matrix() - M.Inverse().matrix()).cwiseAbs().maxCoeff(), 1e-6);
  ASSERT_TRUE(r.rpe.has_value()) << r.rpe_note;
  EXPECT_GT(r.rpe->pairs.size(), 500u);
  EXPECT_LT(r.rpe->trans.rmse, 1e-6);
  EXPECT_LT(r.rpe->rot_deg.rmse, 1e-5);  // 9-digit quaternions and arccos resolution
}

TEST(EvalTumData, AlternatingOffsetGivesTheOffset) {
  SGSLAM_REQUIRE_SHARED(dir, "data/tum_fr1_rpy");
  const std::filesystem::path gt_path = dir / "groundtruth.txt";
  Trajectory est = ReadTumTrajectory(gt_path);
  const Eigen::Vector3d u = Eigen::Vector3d(1.0, 1.0, -0.5).normalized();
  for (std::size_t i = 0; i < est.size(); ++i) {
    const double d = i % 2 == 0 ? 0.01 : -0.01;
    est[i].T_w_c = SE3(est[i].T_w_c.quaternion(), est[i].T_w_c.translation() + d * u);
  }
  TempDir tmp;
  WriteTumTrajectory(tmp / "est.txt", est);
  const EvalReport r = EvaluateFiles(gt_path, tmp / "est.txt");
  EXPECT_NEAR(r.ate.stats.rmse, 0.01, 1e-4);
  EXPECT_NEAR(r.ate.stats.mean, 0.01, 1e-4);
  EXPECT_NEAR(r.ate.stats.median, 0.01, 1e-4);
}

TEST(EvalTumData, StampsShiftedBeyondTheMaxDifferenceDoNotAssociate) {
  SGSLAM_REQUIRE_SHARED(dir, "data/tum_fr1_rpy");
  const std::filesystem::path gt_path = dir / "groundtruth.txt";
  // The gt runs at 100 Hz, so a 0.05 s shift lands on another gt pose; thin both
  // to 10 Hz so the shifted stamps fall halfway between gt poses, 50 ms from each.
  const Trajectory gt10 = Every(ReadTumTrajectory(gt_path), 10);
  const auto shifted = [&](double s) {
    Trajectory est = gt10;
    for (StampedPose& p : est) p.t += FromSeconds(s);
    return est;
  };
  TempDir tmp;
  WriteTumTrajectory(tmp / "gt.txt", gt10);
  WriteTumTrajectory(tmp / "est.txt", shifted(0.015));
  EXPECT_EQ(EvaluateFiles(tmp / "gt.txt", tmp / "est.txt").ate.stats.count, gt10.size());
  WriteTumTrajectory(tmp / "est.txt", shifted(0.05));
  try {
    EvaluateFiles(tmp / "gt.txt", tmp / "est.txt");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no pose of " + (tmp / "est.txt").string()), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace sgslam::eval
