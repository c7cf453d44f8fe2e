// Ground truth and trajectories in the TUM format (io/trajectory.h).
#include <algorithm>
#include <cmath>

#include "fuzz_support.h"
#include "sgslam/io/trajectory.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace sgslam;
  const auto path = fuzz::WriteScratch("groundtruth.txt", fuzz::Bytes(data, size));
  fuzz::Parse([&] {
    const Trajectory trajectory = ReadTumTrajectory(path);
    FUZZ_CHECK(std::is_sorted(trajectory.begin(), trajectory.end(),
                              [](const StampedPose& a, const StampedPose& b) { return a.t < b.t; }));
    for (const StampedPose& p : trajectory) {
      FUZZ_CHECK(p.T_w_c.translation().allFinite());
      FUZZ_CHECK(std::abs(p.T_w_c.quaternion().norm() - 1) < 1e-6);
    }
  });
  return 0;
}
