// semantic.min_view_support: on export, a cloud point stays only when enough
// keyframes put points near it. Five keyframes of a wall at 4 m from slightly
// different places; a patch at 2 m is in one keyframe only (something that passed
// through), another in three (something that stayed). The see-through filter and
// the border strip are off, so that this filter alone decides.
#include <gtest/gtest.h>

#include <shared_mutex>

#include "sgslam/map/features.h"
#include "sgslam/map/keyframe.h"
#include "sgslam/map/map.h"
#include "sgslam/semantic/semantic_mapper.h"
#include "semantic/semantic_scenes.h"

namespace sgslam {
namespace {

struct Cloud {
  std::size_t wall = 0, passing = 0, staying = 0, unsupported = 0;
};

Cloud BuildCloud(int min_view_support) {
  Config config;
  config.camera = test::PinholeCamera();
  config.semantic.consistency_filter = false;
  config.semantic.free_space_filter = false;
  config.semantic.box_window = 0;
  config.semantic.min_view_support = min_view_support;
  config.semantic.cloud_border = 0;  // the whole wall, to the image edge
  Map map;
  SemanticMapper mapper(config, map, /*sequential=*/true);
  const auto camera = std::make_shared<Camera>(config.camera);
  const auto scale = std::make_shared<ScaleLevels>(features::MakeScaleLevels(1.2, 8));
  const cv::Mat bgr(480, 640, CV_8UC3, cv::Scalar(90, 120, 150));
  for (int k = 0; k < 5; ++k) {
    cv::Mat depth(480, 640, CV_16UC1, cv::Scalar(4 * 5000));
    if (k == 2) depth(cv::Rect(100, 100, 60, 60)).setTo(2 * 5000);  // passing: x ~ -0.9 m at 2 m
    if (k <= 2) depth(cv::Rect(450, 300, 60, 60)).setTo(2 * 5000);  // staying: x ~ +0.6 m at 2 m
    auto f = MakeFeatures({}, cv::Mat(0, 32, CV_8U), depth, camera, scale);
    // The camera steps sideways by 5 mm a keyframe: the patches stay within a voxel.
    const SE3 T_c_w(Eigen::Quaterniond::Identity(), Eigen::Vector3d(-0.005 * k, 0, 0));
    auto kf = std::make_shared<KeyFrame>(map.NewKeyFrameId(), static_cast<std::uint64_t>(k), 0, f, T_c_w);
    map.AddKeyFrame(kf);
    mapper.Submit({kf, bgr, depth});
  }
  mapper.Finish();
  std::vector<Eigen::Vector3d> points;
  std::vector<Rgb> colours;
  {
    std::shared_lock lock(map.mutex());
    mapper.ExportCloud(points, colours);
  }
  Cloud c;
  for (const Eigen::Vector3d& p : points) {
    if (p.z() > 3.5) ++c.wall;
    else if (p.x() < 0) ++c.passing;
    else ++c.staying;
  }
  c.unsupported = mapper.unsupported_points();
  return c;
}

TEST(ViewSupport, PointsOnlyOneKeyframeSawLeaveTheCloud) {
  const Cloud off = BuildCloud(1);
  EXPECT_GT(off.passing, 50u);
  EXPECT_GT(off.staying, 50u);
  EXPECT_EQ(off.unsupported, 0u);

  const Cloud on = BuildCloud(3);
  EXPECT_EQ(on.passing, 0u);
  EXPECT_EQ(on.staying, off.staying);
  EXPECT_GT(on.unsupported, 0u);
  // Every part of the wall is seen by at least two keyframes (where the patches
  // hide it, the last two see it): it stays whole.
  EXPECT_GE(on.wall, off.wall - off.wall / 100);
}

}  // namespace
}  // namespace sgslam
