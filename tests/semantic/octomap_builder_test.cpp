// OctoMapBuilder on trees that stay empty: inserts with no point in range must not
// crash the finalisation or the file written (camera.depth_factor 1000 on depth
// scaled by 5000 put every point beyond range and ended `sgslam run` with SIGSEGV).
#include <gtest/gtest.h>

#include <octomap/OcTree.h>

#include <fstream>

#include "sgslam/semantic/octomap_builder.h"
#include "support/test_support.h"

namespace sgslam {
namespace {

TEST(OctoMapBuilder, EmptyInsertFinalizesAndWritesAnEmptyTree) {
  OctoMapBuilder builder{SemanticConfig{}};
  builder.Insert({}, {}, SE3());
  builder.Finalize();
  EXPECT_EQ(builder.OccupiedLeaves(), 0u);

  const test::TempDir dir;
  builder.Insert({}, {}, SE3());
  const auto path = dir.path() / "empty.bt";
  builder.Write(path);
  octomap::OcTree tree(0.1);
  ASSERT_TRUE(tree.readBinary(path.string()));
  EXPECT_EQ(tree.size(), 0u);
}

TEST(OctoMapBuilder, ClearedAfterInsertsFinalizes) {
  OctoMapBuilder builder{SemanticConfig{}};
  ColoredPoint p;
  p.p = Eigen::Vector3f(0, 0, 2);
  builder.Insert({p}, {p}, SE3());
  builder.Finalize();
  EXPECT_EQ(builder.OccupiedLeaves(), 1u);
  builder.Clear();
  builder.Insert({}, {}, SE3());
  builder.Finalize();
  EXPECT_EQ(builder.OccupiedLeaves(), 0u);
}

}  // namespace
}  // namespace sgslam
