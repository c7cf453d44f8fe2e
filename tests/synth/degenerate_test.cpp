// The degenerate preset: a person moving parallel to the camera's translation, whose
// image motion therefore stays on the epipolar lines.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "sgslam/synth/sequence.h"

namespace sgslam::synth {
namespace {

const SceneObject& TheWalker(const SynthSequence& seq) {
  for (const SceneObject& o : seq.objects()) {
    if (o.info.dynamic) return o;
  }
  throw std::runtime_error("no moving object");
}

TEST(SynthDegenerate, WalkerMovesParallelToTheCameraWithLittleRotation) {
  const SynthSequence seq("degenerate", 1, 300);
  const int id = TheWalker(seq).info.id;
  int compared = 0;
  for (int i = 0; i + 1 < seq.size(); ++i) {
    const SE3 a = seq.CameraPose(i), b = seq.CameraPose(i + 1);
    const double dt = seq.Seconds(i + 1) - seq.Seconds(i);
    EXPECT_LT(a.quaternion().angularDistance(b.quaternion()) / dt * 180 / std::numbers::pi, 1.0);  // deg/s
    EXPECT_LT(a.quaternion().angularDistance(seq.CameraPose(0).quaternion()) * 180 / std::numbers::pi, 1.5);
    const Eigen::Vector3d camera_step = b.translation() - a.translation();
    const Eigen::Vector3d walker_velocity = seq.ObjectVelocity(id, i);
    if (camera_step.norm() < 0.05 * dt || walker_velocity.norm() < 0.05) continue;
    const double cosine = std::abs(camera_step.normalized().dot(walker_velocity.normalized()));
    EXPECT_GT(cosine, std::cos(2.0 * std::numbers::pi / 180)) << "frame " << i;
    ++compared;
  }
  EXPECT_GT(compared, 200);
}

TEST(SynthDegenerate, WalkerImageMotionStaysOnEpipolarLines) {
  const SynthSequence seq("degenerate", 2, 120);
  const SceneObject& walker = TheWalker(seq);
  const Intrinsics& K = seq.intrinsics();
  Eigen::Matrix3d Kmat;
  Kmat << K.fx, 0, K.cx, 0, K.fy, K.cy, 0, 0, 1;
  int visible_frames = 0;
  for (int i = 0; i + 10 < seq.size(); i += 10) {
    const SE3 T_c1_c0 = seq.CameraPose(i + 10).Inverse() * seq.CameraPose(i);
    if (T_c1_c0.translation().norm() < 0.01) continue;
    const Eigen::Matrix3d E = Hat(T_c1_c0.translation().normalized()) * T_c1_c0.rotation();
    const Eigen::Matrix3d F = Kmat.inverse().transpose() * E * Kmat.inverse();
    bool seen = false;
    for (const Quad& q : walker.quads) {  // the walker's box corners, in its own frame
      const Eigen::Vector3d p0 = seq.CameraPose(i).Inverse() * (seq.ObjectPose(walker.info.id, i) * q.centre);
      const Eigen::Vector3d p1 = seq.CameraPose(i + 10).Inverse() * (seq.ObjectPose(walker.info.id, i + 10) * q.centre);
      if (p0.z() < 0.5 || p1.z() < 0.5) continue;
      const Eigen::Vector3d x0 = Kmat * p0 / p0.z(), x1 = Kmat * p1 / p1.z();
      if (x0.x() < 0 || x0.x() > K.width || x1.x() < 0 || x1.x() > K.width) continue;
      const Eigen::Vector3d line = F * x0;
      const double distance = std::abs(x1.dot(line)) / line.head<2>().norm();
      EXPECT_LT(distance, 0.5) << "frame " << i;  // a static point would also give ~0
      seen = true;
    }
    visible_frames += seen;
  }
  EXPECT_GE(visible_frames, 4);
}

}  // namespace
}  // namespace sgslam::synth
