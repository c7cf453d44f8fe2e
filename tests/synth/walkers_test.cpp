#include <gtest/gtest.h>

#include <cstdio>

#include "sgslam/synth/sequence.h"

namespace sgslam::synth {
namespace {

TEST(SynthWalkers, PeopleCoverAFifthToHalfOfTheImageInManyFrames) {
  for (std::uint32_t seed : {1u, 2u}) {
    const SynthSequence seq("walkers", seed, 120);
    int in_range = 0;
    double sum = 0;
    for (int i = 0; i < seq.size(); ++i) {
      const double fraction = seq.Render(i).dynamic_fraction;
      in_range += fraction >= 0.2 && fraction <= 0.5;
      sum += fraction;
    }
    std::printf("seed %u: %d of %d frames with a dynamic fraction in [0.2, 0.5], mean %.3f\n", seed, in_range,
                seq.size(), sum / seq.size());
    EXPECT_GE(in_range, 0.3 * seq.size()) << "seed " << seed;
  }
}

TEST(SynthWalkers, AtLeastTwoPeopleWalkAtWalkingSpeedInsideTheRoom) {
  const SynthSequence seq("walkers", 1, 300);
  int people = 0;
  for (const SceneObject& o : seq.objects()) {
    if (!o.info.dynamic) continue;
    ++people;
    EXPECT_EQ(o.info.class_name, "person");
    EXPECT_EQ(o.info.class_id, 0);
    EXPECT_NEAR(o.info.size.z(), 1.75, 0.01);
    double sum = 0, max = 0;
    for (int i = 0; i < seq.size(); ++i) {
      const Eigen::Vector3d v = seq.ObjectVelocity(o.info.id, i);
      sum += v.norm();
      max = std::max(max, v.norm());
      EXPECT_NEAR(v.z(), 0, 1e-12);
      const Eigen::Vector3d p = seq.ObjectPose(o.info.id, i).translation();
      EXPECT_TRUE((p.head<2>().array() > 0.4).all() && (p.head<2>().array() < seq.scene().room_size.head<2>().array() - 0.4).all());
      if (i + 1 < seq.size()) {  // the analytic velocity matches the poses
        const Eigen::Vector3d step = seq.ObjectPose(o.info.id, i + 1).translation() - p;
        EXPECT_NEAR(step.norm() / (seq.Seconds(i + 1) - seq.Seconds(i)), 0.5 * (v.norm() + seq.ObjectVelocity(o.info.id, i + 1).norm()), 0.1);
      }
    }
    const double mean = sum / seq.size();
    std::printf("person %d: mean speed %.2f m/s, max %.2f m/s\n", o.info.id, mean, max);
    EXPECT_GT(mean, 0.7);
    EXPECT_LT(max, 1.4);
  }
  EXPECT_GE(people, 2);
}

}  // namespace
}  // namespace sgslam::synth
