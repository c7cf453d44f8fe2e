// semantic.filters.view_support: on export, a cloud point stays only when enough
// keyframes (kMinViewSupport, 3) put points near it. Five keyframes of a wall at 4 m
// from slightly different places; a patch at 2 m is in one keyframe only (something
// that passed through), another in three (something that stayed). The see-through
// and free-space filters, the box window and the border strip are off (nothing is
// masked, so seen-moving drops nothing), so that this filter alone decides.
#include <gtest/gtest.h>

#include "semantic/semantic_scenes.h"
#include "semantic/stepped_keyframes.h"

namespace sgslam {
namespace {

struct Cloud {
  std::size_t wall = 0, passing = 0, staying = 0, unsupported = 0;
};

Cloud BuildCloud(bool view_support) {
  Config config;
  config.camera = test::PinholeCamera();
  SemanticFilters& f = config.semantic.filters;
  f.see_through = false;
  f.free_space = false;
  f.box_window = false;
  f.view_support = view_support;
  f.image_border = false;  // the whole wall, to the image edge
  std::vector<cv::Mat> depths;
  for (int k = 0; k < 5; ++k) {
    cv::Mat depth(480, 640, CV_16UC1, cv::Scalar(4 * 5000));
    if (k == 2) depth(cv::Rect(100, 100, 60, 60)).setTo(2 * 5000);  // passing: x ~ -0.9 m at 2 m
    if (k <= 2) depth(cv::Rect(450, 300, 60, 60)).setTo(2 * 5000);  // staying: x ~ +0.6 m at 2 m
    depths.push_back(depth);
  }
  const test::SteppedCloud cloud = test::ExportSteppedKeyframes(config, depths);
  Cloud c;
  for (const Eigen::Vector3d& p : cloud.points) {
    if (p.z() > 3.5) ++c.wall;
    else if (p.x() < 0) ++c.passing;
    else ++c.staying;
  }
  c.unsupported = cloud.unsupported;
  return c;
}

TEST(ViewSupport, PointsOnlyOneKeyframeSawLeaveTheCloud) {
  const Cloud off = BuildCloud(false);
  EXPECT_GT(off.passing, 50u);
  EXPECT_GT(off.staying, 50u);
  EXPECT_EQ(off.unsupported, 0u);

  ASSERT_EQ(kMinViewSupport, 3);  // the staying patch is in exactly 3 keyframes
  const Cloud on = BuildCloud(true);
  EXPECT_EQ(on.passing, 0u);
  EXPECT_EQ(on.staying, off.staying);
  EXPECT_GT(on.unsupported, 0u);
  // Every part of the wall is seen by at least two keyframes (where the patches
  // hide it, the last two see it): it stays whole.
  EXPECT_GE(on.wall, off.wall - off.wall / 100);
}

}  // namespace
}  // namespace sgslam
