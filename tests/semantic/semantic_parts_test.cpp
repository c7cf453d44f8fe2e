// The pieces of the semantic map on small synthetic inputs with known answers.
#include <gtest/gtest.h>

#include <octomap/OcTree.h>

#include "sgslam/camera/camera.h"
#include "sgslam/common/error.h"
#include "sgslam/config/config.h"
#include "sgslam/semantic/background_planes.h"
#include "sgslam/semantic/cloud.h"
#include "sgslam/semantic/dynamic_mask.h"
#include "sgslam/semantic/objects.h"
#include "sgslam/semantic/octomap_builder.h"
#include "semantic/semantic_scenes.h"
#include "support/test_support.h"

namespace sgslam {
namespace {

using test::FaceBeforeWall;
using test::PinholeCamera;

TEST(VoxelDownsample, OnePointPerVoxelAtTheMean) {
  const std::vector<ColoredPoint> in = {{{0.01f, 0.01f, 0.01f}, {0, 0, 0}},
                                        {{0.03f, 0.01f, 0.01f}, {100, 50, 10}},
                                        {{0.51f, 0.0f, 0.0f}, {7, 7, 7}}};
  const auto out = VoxelDownsample(in, 0.1);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_NEAR(out[0].p.x(), 0.02f, 1e-6);
  EXPECT_EQ(out[0].rgb, (Rgb{50, 25, 5}));
  EXPECT_NEAR(out[1].p.x(), 0.51f, 1e-6);
}

TEST(BackProject, PixelsLandOnTheirDepthAndMaskedOnesAreLeftOut) {
  const Camera cam(PinholeCamera());
  const PixelRays rays(cam);
  const cv::Mat depth = FaceBeforeWall();
  cv::Mat mask = cv::Mat::zeros(depth.size(), CV_8UC1);
  mask(cv::Rect(200, 150, 100, 180)).setTo(255);
  SemanticConfig c;
  c.filters.depth_edges = false;  // the outline's pixels: next test
  const auto all = BackProject(cv::Mat(), depth, 5000, cv::Mat(), rays, 4, c);
  const auto kept = BackProject(cv::Mat(), depth, 5000, mask, rays, 4, c);
  EXPECT_EQ(all.size(), 160u * 120u);
  EXPECT_EQ(all.size() - kept.size(), 25u * 45u);
  for (const auto& p : kept) EXPECT_NEAR(p.p.z(), 4.0f, 1e-6);
  c.depth_max = 3.0;  // the wall is out of range now
  EXPECT_EQ(BackProject(cv::Mat(), depth, 5000, cv::Mat(), rays, 4, c).size(), 25u * 45u);
}

// With filters.depth_edges, pixels within kDepthEdgeRadius of a depth step, on
// either side, are left out: the ring of Chebyshev radius 2 around the face's
// outline (2 m against 4 m).
TEST(BackProject, PixelsAtDepthStepsAreLeftOut) {
  const Camera cam(PinholeCamera());
  const PixelRays rays(cam);
  cv::Mat depth = FaceBeforeWall();
  SemanticConfig c;
  ASSERT_TRUE(c.filters.depth_edges);
  ASSERT_EQ(kDepthEdgeRadius, 2);
  const std::size_t face_ring = 100 * 180 - 96 * 176, wall_ring = 104 * 184 - 100 * 180;
  EXPECT_EQ(BackProject(cv::Mat(), depth, 5000, cv::Mat(), rays, 1, c).size(), 640u * 480u - face_ring - wall_ring);
  // A step below the threshold (0.05 m + 0.02 / m * z^2 = 0.37 m at 4 m) is a surface.
  depth(cv::Rect(200, 150, 100, 180)).setTo(static_cast<int>(3.7 * 5000));
  EXPECT_EQ(BackProject(cv::Mat(), depth, 5000, cv::Mat(), rays, 1, c).size(), 640u * 480u);
  // Holes next to a pixel do not make it an edge (there is no depth to compare).
  depth = FaceBeforeWall();
  depth(cv::Rect(200, 150, 100, 180)).setTo(0);
  EXPECT_EQ(BackProject(cv::Mat(), depth, 5000, cv::Mat(), rays, 1, c).size(), 640u * 480u - 100u * 180u);
  c.filters.depth_edges = false;
  depth = FaceBeforeWall();
  EXPECT_EQ(BackProject(cv::Mat(), depth, 5000, cv::Mat(), rays, 1, c).size(), 640u * 480u);
}

TEST(DynamicPixelMask, PersonBoxesAndRejectedKeypointsButNotChairs) {
  DetectorConfig dc;
  const ClassTable classes(dc);
  const cv::Mat depth = FaceBeforeWall();
  DynamicMaskOptions c;
  c.box_margin = 0.1;  // 20 px above the box
  Detection person{0, "person", 0.9f, cv::Rect2f(400, 100, 100, 200)};
  Detection chair{56, "chair", 0.9f, cv::Rect2f(20, 20, 50, 50)};
  // A rejected keypoint on the box face (2 m) outside any box: only the 2 m pixels
  // within the radius are masked, not the wall around.
  const std::vector<cv::KeyPoint> keys = {cv::KeyPoint(250, 240, 7), cv::KeyPoint(100, 400, 7)};
  const std::vector<std::uint8_t> rejected = {1, 0};
  const cv::Mat m = DynamicPixelMask(depth, 5000, {person, chair}, classes, keys, rejected, c);
  EXPECT_EQ(m.at<std::uint8_t>(100, 450), 255);  // person box
  EXPECT_EQ(m.at<std::uint8_t>(95, 450), 255);   // its margin
  EXPECT_EQ(m.at<std::uint8_t>(40, 40), 0);      // chair: a static class
  EXPECT_EQ(m.at<std::uint8_t>(240, 260), 255);  // near the rejected keypoint, same depth
  EXPECT_EQ(m.at<std::uint8_t>(240, 305), 0);    // within the radius, but the wall behind
  EXPECT_EQ(m.at<std::uint8_t>(400, 100), 0);    // kept keypoint
}

// The depth segments alone (no motion radius) on a face at 2 m on [200, 300) x
// [150, 330) before a wall at 4 m.
struct SegmentsOnly {
  DetectorConfig dc;
  const ClassTable classes{dc};
  const cv::Mat depth = FaceBeforeWall();
  DynamicMaskOptions c = [] {
    DynamicMaskOptions s;
    s.motion_radius = 0;
    return s;
  }();
};

TEST(DynamicPixelMask, MasksTheWholeDepthSegmentWhereMostKeypointsMoved) {
  const SegmentsOnly t;
  const ClassTable& classes = t.classes;
  const cv::Mat& depth = t.depth;
  const DynamicMaskOptions& c = t.c;
  std::vector<cv::KeyPoint> keys;
  for (int k = 0; k < 4; ++k) keys.emplace_back(220.f + 20.f * static_cast<float>(k), 170.f, 7.f);  // top of the face
  keys.emplace_back(250.f, 300.f, 7.f);  // one kept on the face
  keys.emplace_back(500.f, 400.f, 7.f);  // kept on the wall
  std::vector<std::uint8_t> rejected = {1, 1, 1, 1, 0, 0};
  cv::Mat m = DynamicPixelMask(depth, 5000, {}, classes, keys, rejected, c);
  EXPECT_EQ(m.at<std::uint8_t>(320, 210), 255);  // the far corner of the face, 150 px from the votes
  EXPECT_EQ(m.at<std::uint8_t>(240, 350), 0);    // wall
  EXPECT_EQ(m.at<std::uint8_t>(100, 250), 0);    // wall above the face
  // Rejected keypoints in the minority of their segment: noise, not a moving object.
  for (int k = 0; k < 5; ++k) {
    keys.emplace_back(210.f + 20.f * static_cast<float>(k), 250.f, 7.f);
    rejected.push_back(0);
  }
  m = DynamicPixelMask(depth, 5000, {}, classes, keys, rejected, c);
  EXPECT_EQ(cv::countNonZero(m), 0);
}

TEST(DynamicPixelMask, KeypointsKeptWithoutATestDoNotOutvoteTheMovingOnes) {
  // A walker entering the view: its keypoints near the border have no flow pair
  // and are kept untested (dyn_dev frames 128-134: 47-82 such keypoints a frame
  // against 9-25 rejected); they must not count as static votes for the segment.
  SegmentsOnly t;
  const ClassTable& classes = t.classes;
  const cv::Mat& depth = t.depth;
  DynamicMaskOptions& c = t.c;
  std::vector<cv::KeyPoint> keys;
  std::vector<std::uint8_t> rejected, unjudged;
  for (int k = 0; k < 3; ++k) {  // rejected on the face
    keys.emplace_back(220.f + 20.f * static_cast<float>(k), 170.f, 7.f);
    rejected.push_back(1), unjudged.push_back(0);
  }
  for (int k = 0; k < 5; ++k) {  // kept untested on the face
    keys.emplace_back(210.f + 20.f * static_cast<float>(k), 300.f, 7.f);
    rejected.push_back(0), unjudged.push_back(1);
  }
  keys.emplace_back(500.f, 400.f, 7.f);  // kept after a test, on the wall
  rejected.push_back(0), unjudged.push_back(0);
  cv::Mat m = DynamicPixelMask(depth, 5000, {}, classes, keys, rejected, c, unjudged);
  EXPECT_EQ(m.at<std::uint8_t>(320, 210), 255);  // the face
  EXPECT_EQ(m.at<std::uint8_t>(240, 350), 0);    // the wall
  c.skip_unjudged = false;  // counted as static: 3 of 8 rejected, not masked
  m = DynamicPixelMask(depth, 5000, {}, classes, keys, rejected, c, unjudged);
  EXPECT_EQ(cv::countNonZero(m), 0);
  // Tested keypoints still outvote: the same five, tested and kept, leave it unmasked.
  c.skip_unjudged = true;
  std::fill(unjudged.begin(), unjudged.end(), 0);
  m = DynamicPixelMask(depth, 5000, {}, classes, keys, rejected, c, unjudged);
  EXPECT_EQ(cv::countNonZero(m), 0);
}

TEST(ObserveObject, TakesTheObjectDepthsOfTheWholeBox) {
  const Camera cam(PinholeCamera());
  const PixelRays rays(cam);
  SemanticConfig c;
  // The box is drawn 20 px larger than the object on every side: wall in its border.
  const Detection d{56, "chair", 0.8f, cv::Rect2f(180, 130, 140, 220)};
  const auto obs = ObserveObject(d, FaceBeforeWall(), 5000, rays, c);
  ASSERT_TRUE(obs.has_value());
  EXPECT_GE(static_cast<int>(obs->points_c.size()), kObjectMinPoints);
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(1e9), hi = -lo;
  for (const auto& p : obs->points_c) {
    EXPECT_NEAR(p.z(), 2.0f, 1e-4);
    lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  }
  // The object spans 100 x 180 px at 2 m: 0.4 x 0.72 m, sampled to a few cm.
  EXPECT_NEAR(hi.x() - lo.x(), 0.4, 0.05);
  EXPECT_NEAR(hi.y() - lo.y(), 0.72, 0.05);
  // Too small a box: too few depth samples, no observation.
  EXPECT_FALSE(ObserveObject({56, "chair", 0.8f, cv::Rect2f(10, 10, 4, 4)}, FaceBeforeWall(), 5000, rays, c));
}

// A nearer object (its own detection) hides the left two thirds of the face: the
// face's depth must come from what the other box leaves visible, and the hiding
// object's pixels must not join the face.
TEST(ObserveObject, AnOccluderInItsOwnBoxDoesNotSetTheDepth) {
  const Camera cam(PinholeCamera());
  const PixelRays rays(cam);
  SemanticConfig c;
  cv::Mat depth = FaceBeforeWall();
  depth(cv::Rect(170, 140, 95, 200)).setTo(1.2 * 5000);
  const std::vector<Detection> dets = {{56, "chair", 0.8f, cv::Rect2f(180, 130, 140, 220)},
                                       {62, "tvmonitor", 0.8f, cv::Rect2f(165, 135, 105, 210)}};
  const std::vector<double> z = ObjectDepths(dets, depth, 5000, c);
  ASSERT_EQ(z.size(), 2u);
  EXPECT_NEAR(z[0], 2.0, 1e-3);  // from the face's uncovered columns
  EXPECT_NEAR(z[1], 1.2, 1e-3);  // the whole inner box: the face's box covers it all
  // Without the other box the occluder is the majority of the inner box and wins.
  const auto blind = ObserveObject(dets[0], depth, 5000, rays, c);
  ASSERT_TRUE(blind.has_value());
  EXPECT_NEAR(blind->points_c.front().z(), 1.2f, 1e-3);
  const auto obs = ObserveObject(dets[0], depth, 5000, rays, c, {{dets[1].box, z[1]}});
  ASSERT_TRUE(obs.has_value());
  float x_min = 1e9f;
  for (const auto& p : obs->points_c) {
    EXPECT_NEAR(p.z(), 2.0f, 1e-4);
    x_min = std::min(x_min, p.x());
  }
  // The visible part of the face starts at column 265.
  EXPECT_NEAR(x_min, (265 - 319.5) / 500.0 * 2.0, 0.02);  // sampled every few px
  // An unknown depth (0) leaves the box out of the reasoning.
  const auto unknown = ObserveObject(dets[0], depth, 5000, rays, c, {{dets[1].box, 0.0}});
  ASSERT_TRUE(unknown.has_value());
  EXPECT_NEAR(unknown->points_c.front().z(), 1.2f, 1e-3);
}

// A plant: leaves at 2 m over the upper part of the box, a narrower pot 15 cm
// further back below them, the wall at 4 m. The leaves' flat face gives a MAD of
// the 1 cm floor, and a 3-MAD band alone would cut the pot off; the band of the
// box's width (0.48 m here) keeps it and still drops the wall.
TEST(ObserveObject, ARecessedPartWithinTheBoxWidthBelongsToTheObject) {
  const Camera cam(PinholeCamera());
  const PixelRays rays(cam);
  cv::Mat depth(480, 640, CV_16UC1, cv::Scalar(4 * 5000));
  depth(cv::Rect(200, 150, 100, 108)).setTo(2 * 5000);     // leaves, rows 150-257
  depth(cv::Rect(225, 258, 50, 72)).setTo(2.15 * 5000);  // pot, rows 258-329
  const Detection d{58, "pottedplant", 0.8f, cv::Rect2f(190, 140, 120, 200)};
  const auto lowest = [&](const ObserveObjectOptions& o) {
    const auto obs = ObserveObject(d, depth, 5000, rays, SemanticConfig(), {}, cv::Mat(), o);
    EXPECT_TRUE(obs.has_value());
    float y_max = -1e9f;
    for (const auto& p : obs ? obs->points_c : std::vector<Eigen::Vector3f>{}) {
      EXPECT_LT(p.z(), 2.2f) << "wall point kept";
      y_max = std::max(y_max, p.y());
    }
    return y_max;
  };
  ObserveObjectOptions o;  // the pipeline's
  ASSERT_EQ(o.depth_band_width, 1.0);
  EXPECT_NEAR(lowest(o), (329 - 239.5) / 500.0 * 2.15, 0.03);  // the pot's bottom row
  o.depth_band_width = 0;
  EXPECT_NEAR(lowest(o), (257 - 239.5) / 500.0 * 2.0, 0.03);  // the leaves' bottom row
}

TEST(FitPlanes, FindsFloorAndWallButNotTheClutterBetween) {
  std::vector<Eigen::Vector3f> pts;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j) {
      pts.emplace_back(-1.0f + 0.1f * static_cast<float>(i), 0.8f, 1.5f + 0.1f * static_cast<float>(j));  // floor y = 0.8
      if (j < 12) pts.emplace_back(-1.0f + 0.1f * static_cast<float>(i), -0.4f + 0.1f * static_cast<float>(j), 4.0f);  // wall
    }
  std::vector<Eigen::Vector3f> clutter;
  for (int i = 0; i < 60; ++i)  // scattered points near neither plane
    clutter.emplace_back(0.3f * std::sin(1.7f * static_cast<float>(i)), 0.2f * std::cos(2.3f * static_cast<float>(i)),
                         2.5f + 0.5f * std::sin(0.9f * static_cast<float>(i)));
  pts.insert(pts.end(), clutter.begin(), clutter.end());
  PlaneFitOptions o;
  o.tolerance = 0.02f;
  const std::vector<Plane> planes = FitPlanes(pts, o);
  ASSERT_EQ(planes.size(), 2u);
  EXPECT_GT(std::abs(planes[0].normal.y()), 0.999f) << "the floor holds the most points";
  EXPECT_NEAR(planes[0].Distance(Eigen::Vector3f::Zero()), 0.8f, 1e-3);
  EXPECT_GT(std::abs(planes[1].normal.z()), 0.999f);
  EXPECT_NEAR(planes[1].Distance(Eigen::Vector3f::Zero()), 4.0f, 1e-3);
  for (const auto& p : clutter)
    for (const Plane& pl : planes) EXPECT_FALSE(OnPlane(pl, p, o)) << p.transpose();
  // Same input, same planes (fixed RANSAC seed).
  const std::vector<Plane> again = FitPlanes(pts, o);
  ASSERT_EQ(again.size(), planes.size());
  EXPECT_EQ(again[0].normal, planes[0].normal);
  // Too few points for any plane.
  EXPECT_TRUE(FitPlanes(std::vector<Eigen::Vector3f>(clutter.begin(), clutter.begin() + 20), o).empty());
}

// A slanted face (1.8 to 2.2 m) standing on a floor 0.8 m below the camera, a wall
// at 4 m behind; the box is drawn 20 px wider than the face on each side.
TEST(ObserveObject, FloorInTheBoxIsBackgroundNotObject) {
  const Camera cam(PinholeCamera());
  const PixelRays rays(cam);
  cv::Mat depth(480, 640, CV_16UC1);
  const auto face_z = [](int u) { return 1.8 + 0.4 * (u - 250) / 140.0; };
  for (int v = 0; v < 480; ++v)
    for (int u = 0; u < 640; ++u) {
      double z = v > 339.5 ? 400.0 / (v - 239.5) : 4.0;  // floor below the horizon's wall line, else wall
      if (u >= 250 && u < 390 && v >= 200 && v <= 239.5 + 400.0 / face_z(u)) z = face_z(u);
      depth.at<std::uint16_t>(v, u) = static_cast<std::uint16_t>(std::lround(z * 5000));
    }
  const Detection d{56, "chair", 0.8f, cv::Rect2f(230, 180, 180, 290)};
  const auto extent = [&](const ObserveObjectOptions& o) {
    const auto obs = ObserveObject(d, depth, 5000, rays, SemanticConfig(), {}, cv::Mat(), o);
    EXPECT_TRUE(obs.has_value());
    Eigen::Vector3f lo = Eigen::Vector3f::Constant(1e9), hi = -lo;
    for (const auto& p : obs ? obs->points_c : std::vector<Eigen::Vector3f>{}) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    return std::pair(lo, hi);
  };
  ObserveObjectOptions o;  // the pipeline's
  ASSERT_GT(o.background_planes, 0);
  const auto [lo, hi] = extent(o);
  // The face spans x = -69.5 * 1.8 / 500 = -0.25 to 70.5 * 2.2 / 500 = 0.31 m.
  EXPECT_NEAR(lo.x(), -0.25, 0.03);
  EXPECT_NEAR(hi.x(), 0.31, 0.03);
  EXPECT_GT(lo.z(), 1.77);
  EXPECT_LT(hi.y(), 0.8);
  // Without the step the floor in the box border widens and deepens the object.
  o.background_planes = 0;
  const auto [lo0, hi0] = extent(o);
  EXPECT_LT(lo0.x(), -0.3);
  EXPECT_LT(lo0.z(), 1.76);
}

TEST(OctoMapBuilder, WallIsOccupiedTheSpaceBeforeItFreeAndTheFileReloads) {
  SemanticConfig c;
  OctoMapBuilder map(c);
  std::vector<ColoredPoint> wall;
  for (int i = -20; i <= 20; ++i)
    for (int j = -20; j <= 20; ++j) wall.push_back({{0.02f * i, 0.02f * j, 3.0f}, {200, 10, 10}});
  map.Insert(wall, wall, SE3());
  map.Finalize();
  EXPECT_GT(map.OccupiedLeaves(), 100u);
  EXPECT_TRUE(map.IsFree({0.0, 0.0, 1.5}));
  EXPECT_FALSE(map.IsFree({0.0, 0.0, 3.0}));
  EXPECT_FALSE(map.IsFree({5.0, 5.0, 5.0}));  // never observed: unknown, not free
  test::TempDir dir;
  map.Write(dir / "wall.bt");
  octomap::OcTree back(0.1);
  ASSERT_TRUE(back.readBinary((dir / "wall.bt").string()));
  std::size_t occupied = 0;
  for (auto it = back.begin_leafs(); it != back.end_leafs(); ++it) occupied += back.isNodeOccupied(*it);
  EXPECT_EQ(occupied, map.OccupiedLeaves());
  test::WriteText(dir / "a_file", "x");  // no folder can be made under a file
  EXPECT_THROW(map.Write(dir / "a_file" / "x.bt"), InputError);
}

TEST(SemanticConfig, BadValuesNameTheirKey) {
  Config c;
  c.semantic.octomap_resolution = 2.0;
  c.semantic.depth_max = 0.1;
  c.semantic.keyframe_model = "models/yolo-fastest-1.1-xl";  // a path, not a stem
  try {
    c.Validate("test.yaml");
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("semantic.octomap_resolution = 2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("semantic.depth_max"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("semantic.keyframe_model"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace sgslam
