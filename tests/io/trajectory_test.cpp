// TUM trajectory files: what is read back, and the lines that are refused.
#include "sgslam/io/trajectory.h"

#include <gtest/gtest.h>

#include "sgslam/common/error.h"
#include "support/test_support.h"

namespace sgslam {
namespace {

TEST(Trajectory, ReadsSortedUnitQuaternions) {
  test::TempDir dir;
  const auto path = dir / "groundtruth.txt";
  test::WriteText(path, "# t tx ty tz qx qy qz qw\n2 1 2 3 0 0 0 2\n1,0,0,0,0,0,1,0\n");
  const Trajectory t = ReadTumTrajectory(path);
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[0].t, kNsPerSecond);
  EXPECT_NEAR(t[0].T_w_c.quaternion().z(), 1.0, 1e-12);
  EXPECT_NEAR(t[1].T_w_c.quaternion().w(), 1.0, 1e-12);
  EXPECT_EQ(t[1].T_w_c.translation(), Eigen::Vector3d(1, 2, 3));
}

// A norm that overflowed to infinity used to normalise the quaternion to zero
// instead of refusing the line (the fuzz target checks every pose's quaternion).
TEST(Trajectory, QuaternionsOfZeroOrOverflowingNormNameTheLine) {
  for (const std::string q : {"0 0 0 0", "1e200 1e200 0 1e200", "0 0 0 1e300"}) {
    test::TempDir dir;
    const auto path = dir / "groundtruth.txt";
    test::WriteText(path, "1 0 0 0 0 0 0 1\n2 0 0 0 " + q + "\n");
    try {
      ReadTumTrajectory(path);
      ADD_FAILURE() << "no error for the quaternion " << q;
    } catch (const ParseError& e) {
      EXPECT_NE(std::string(e.what()).find(path.string() + ":2:"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("quaternion"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace sgslam
