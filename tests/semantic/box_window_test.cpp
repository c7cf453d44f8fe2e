// Carrying dynamic boxes between frames (box_window.h) on a pinhole camera with
// known motion: where the box lands, what it masks, and what it refuses.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "sgslam/camera/camera.h"
#include "sgslam/config/config.h"
#include "sgslam/semantic/box_window.h"
#include "semantic/semantic_scenes.h"

namespace sgslam {
namespace {

using test::FaceBeforeWall;
using test::PinholeCamera;

FrameBoxes Seen(const cv::Rect2f& box, double depth, const SE3& T_c_w = SE3()) {
  FrameBoxes f;
  f.T_c_w = T_c_w;
  f.boxes.push_back({0, "person", 0.9f, box});
  f.depth.push_back(depth);
  return f;
}

TEST(BoxMedianDepth, IsTheObjectsDepthNotTheBackgroundsAroundIt) {
  // A loose box (20 px of wall on every side): its inner 60 % is all face.
  EXPECT_NEAR(BoxMedianDepth(FaceBeforeWall(), 5000, cv::Rect2f(180, 130, 140, 220)), 2.0, 1e-9);
  EXPECT_EQ(BoxMedianDepth(cv::Mat::zeros(480, 640, CV_16UC1), 5000, cv::Rect2f(180, 130, 140, 220)), 0.0);
}

TEST(CarryBoxes, FollowsTheCameraMotionAtTheBoxDepth) {
  const Camera cam(PinholeCamera());
  const cv::Size image(640, 480);
  const cv::Rect2f box(200, 150, 100, 180);
  // The keyframe's camera is 0.2 m to the right of the frame's: a point at 2 m moves
  // fx * 0.2 / 2 = 50 px to the left in its image.
  const SE3 T_c_w_to(Eigen::Quaterniond::Identity(), Eigen::Vector3d(-0.2, 0, 0));
  const std::vector<CarriedBox> out = CarryBoxes(Seen(box, 2.0), T_c_w_to, cam, image, 0.0, 0.5);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].box.x, 150, 1e-3);
  EXPECT_NEAR(out[0].box.y, 150, 1e-3);
  EXPECT_NEAR(out[0].box.width, 100, 1e-3);
  EXPECT_NEAR(out[0].box.height, 180, 1e-3);
  EXPECT_NEAR(out[0].depth, 2.0, 1e-9);

  // Moving 1 m closer: the box grows to twice its size around the principal point's ray.
  const SE3 closer(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0, 0, -1.0));
  const std::vector<CarriedBox> near = CarryBoxes(Seen(box, 2.0), closer, cam, image, 3.0, 0.5);
  ASSERT_EQ(near.size(), 1u);
  EXPECT_NEAR(near[0].box.width, 200 + 6, 1e-2);  // growth on each side
  EXPECT_NEAR(near[0].depth, 1.0, 1e-9);
}

TEST(CarryBoxes, DropsBoxesBehindTheCameraOutsideTheImageOrTooLarge) {
  const Camera cam(PinholeCamera());
  const cv::Size image(640, 480);
  const cv::Rect2f box(200, 150, 100, 180);
  const SE3 past(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0, 0, -3.0));  // 3 m forward: behind
  EXPECT_TRUE(CarryBoxes(Seen(box, 2.0), past, cam, image, 0.0, 0.5).empty());
  const SE3 aside(Eigen::Quaterniond::Identity(), Eigen::Vector3d(-3.0, 0, 0));  // 750 px to the left
  EXPECT_TRUE(CarryBoxes(Seen(box, 2.0), aside, cam, image, 0.0, 0.5).empty());
  EXPECT_TRUE(CarryBoxes(Seen(cv::Rect2f(0, 0, 600, 450), 2.0), SE3(), cam, image, 0.0, 0.5).empty());
  EXPECT_TRUE(CarryBoxes(Seen(box, 0.0), SE3(), cam, image, 0.0, 0.5).empty());  // no depth: not carried
}

TEST(MaskCarriedBoxes, MasksTheObjectsDepthLayerOnly) {
  const cv::Mat depth = FaceBeforeWall();
  cv::Mat mask = cv::Mat::zeros(480, 640, CV_8UC1);
  MaskCarriedBoxes({{cv::Rect2f(180, 130, 140, 220), 2.1}}, depth, 5000, 0.4, mask);
  EXPECT_EQ(cv::countNonZero(mask), 100 * 180);                      // the face, not the wall in the box
  EXPECT_EQ(cv::countNonZero(mask(cv::Rect(200, 150, 100, 180))), 100 * 180);
}

}  // namespace
}  // namespace sgslam
