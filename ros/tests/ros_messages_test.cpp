// The node's conversions between ROS messages and sgslam's types, and its frame
// queue: no ROS master needed.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include <sensor_msgs/image_encodings.h>

#include "ros_messages.h"

namespace sgslam::ros_bridge {
namespace {

template <typename T>
sensor_msgs::Image Message(const std::vector<T>& pixels, int width, int height, const std::string& encoding,
                           int channels = 1, int padding = 0) {
  sensor_msgs::Image m;
  m.width = static_cast<std::uint32_t>(width);
  m.height = static_cast<std::uint32_t>(height);
  m.encoding = encoding;
  m.step = static_cast<std::uint32_t>(width * channels * sizeof(T) + padding);
  m.data.assign(static_cast<std::size_t>(m.step) * height, 0xEE);
  for (int y = 0; y < height; ++y) {
    std::memcpy(&m.data[static_cast<std::size_t>(y) * m.step], &pixels[static_cast<std::size_t>(y) * width * channels],
                width * channels * sizeof(T));
  }
  return m;
}

TEST(RosDepth, MetresBecomeRawUnitsAndInvalidDepthsZero) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const auto m = Message<float>({1.0f, 0.5f, nan, -1.f, inf, 20.f}, 3, 2, "32FC1", 1, 4);
  const Converted c = DepthToRaw(m, 5000);
  ASSERT_TRUE(c.error.empty()) << c.error;
  ASSERT_EQ(c.image.type(), CV_16UC1);
  EXPECT_EQ(c.image.at<std::uint16_t>(0, 0), 5000);
  EXPECT_EQ(c.image.at<std::uint16_t>(0, 1), 2500);
  EXPECT_EQ(c.image.at<std::uint16_t>(0, 2), 0);  // NaN: no depth
  EXPECT_EQ(c.image.at<std::uint16_t>(1, 0), 0);  // negative
  EXPECT_EQ(c.image.at<std::uint16_t>(1, 1), 0);  // infinite
  EXPECT_EQ(c.image.at<std::uint16_t>(1, 2), 0);  // 20 m is past 16 bits at 5000 a metre, not wrapped
}

TEST(RosDepth, MillimetresBecomeRawUnits) {
  const auto m = Message<std::uint16_t>({1000, 0, 2345, 14000}, 2, 2, "16UC1");
  const Converted c = DepthToRaw(m, 5000);
  ASSERT_TRUE(c.error.empty()) << c.error;
  EXPECT_EQ(c.image.at<std::uint16_t>(0, 0), 5000);
  EXPECT_EQ(c.image.at<std::uint16_t>(0, 1), 0);
  EXPECT_EQ(c.image.at<std::uint16_t>(1, 0), 11725);
  EXPECT_EQ(c.image.at<std::uint16_t>(1, 1), 0);  // 14 m: past 16 bits at 5000 a metre
  EXPECT_EQ(DepthToRaw(m, 1000).image.at<std::uint16_t>(1, 1), 14000);
}

TEST(RosDepth, OtherEncodingsAndShortBuffersAreRefusedWithTheReason) {
  const auto m8 = Message<std::uint8_t>({1, 2, 3, 4}, 2, 2, "8UC1");
  EXPECT_NE(DepthToRaw(m8, 5000).error.find("'8UC1'"), std::string::npos);
  auto m = Message<float>({1, 1, 1, 1}, 2, 2, "32FC1");
  m.data.resize(10);
  EXPECT_NE(DepthToRaw(m, 5000).error.find("do not hold"), std::string::npos);
  m = Message<float>({1, 1, 1, 1}, 2, 2, "32FC1");
  m.is_bigendian = true;
  EXPECT_NE(DepthToRaw(m, 5000).error.find("big-endian"), std::string::npos);
  m.width = 0;
  EXPECT_NE(DepthToRaw(m, 5000).error.find("empty"), std::string::npos);
  m = Message<float>({1, 1, 1, 1}, 2, 2, "32FC1", 1, 2);  // rows 10 bytes apart: no whole float
  EXPECT_NE(DepthToRaw(m, 5000).error.find("not a whole number"), std::string::npos);
}

TEST(RosColour, EncodingsBecomeBgr) {
  const auto rgb = Message<std::uint8_t>({10, 20, 30, 40, 50, 60}, 2, 1, "rgb8", 3, 2);
  const Converted c = ColourToBgr(rgb);
  ASSERT_TRUE(c.error.empty()) << c.error;
  EXPECT_EQ(c.image.at<cv::Vec3b>(0, 0), cv::Vec3b(30, 20, 10));
  EXPECT_EQ(c.image.at<cv::Vec3b>(0, 1), cv::Vec3b(60, 50, 40));
  const auto bgr = Message<std::uint8_t>({10, 20, 30}, 1, 1, "bgr8", 3);
  EXPECT_EQ(ColourToBgr(bgr).image.at<cv::Vec3b>(0, 0), cv::Vec3b(10, 20, 30));
  const auto mono = Message<std::uint8_t>({77}, 1, 1, "mono8");
  EXPECT_EQ(ColourToBgr(mono).image.at<cv::Vec3b>(0, 0), cv::Vec3b(77, 77, 77));
  const auto yuv = Message<std::uint8_t>({1, 2}, 1, 1, "yuv422", 2);
  EXPECT_NE(ColourToBgr(yuv).error.find("'yuv422'"), std::string::npos);
}

TEST(RosCameraInfo, IntrinsicsAndDistortionAreTakenAndNonsenseRefused) {
  sensor_msgs::CameraInfo info;
  info.width = 640, info.height = 480;
  info.K = {500, 0, 320, 0, 510, 240, 0, 0, 1};
  info.distortion_model = "plumb_bob";
  info.D = {0.1, -0.2, 0.001, 0.002, 0.3};
  CameraConfig base;
  base.depth_factor = 1000;
  std::string error;
  const auto c = CameraFromInfo(info, base, &error);
  ASSERT_TRUE(c) << error;
  EXPECT_EQ(c->fx, 500);
  EXPECT_EQ(c->fy, 510);
  EXPECT_EQ(c->cy, 240);
  EXPECT_EQ(c->k3, 0.3);
  EXPECT_EQ(c->p2, 0.002);
  EXPECT_EQ(c->depth_factor, 1000);  // kept from the config
  info.D.clear();
  EXPECT_EQ(CameraFromInfo(info, base, &error)->k1, 0);
  info.D = {0.1, 0, 0, 0};
  info.distortion_model = "equidistant";
  EXPECT_FALSE(CameraFromInfo(info, base, &error));
  EXPECT_NE(error.find("equidistant"), std::string::npos);
  info.D.clear();
  info.K = {0, 0, 0, 0, 0, 0, 0, 0, 0};
  EXPECT_FALSE(CameraFromInfo(info, base, &error));
  EXPECT_NE(error.find("not positive"), std::string::npos);
}

TEST(RosOutputs, PoseCloudMarkersAndImage) {
  const SE3 T(Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY())), Eigen::Vector3d(1, 2, 3));
  const auto odom = ToOdometry(T, "map", "camera", ToRosTime(FromSeconds(12.5)));
  EXPECT_EQ(odom.header.frame_id, "map");
  EXPECT_EQ(odom.child_frame_id, "camera");
  EXPECT_DOUBLE_EQ(odom.pose.pose.position.z, 3);
  EXPECT_NEAR(odom.pose.pose.orientation.y, std::sin(0.15), 1e-12);
  EXPECT_EQ(FromRosTime(odom.header.stamp), FromSeconds(12.5));

  const std::vector<Eigen::Vector3f> points = {{1, 2, 3}, {4, 5, 6}};
  const std::vector<Rgb> colours = {Rgb{255, 0, 0}, Rgb{0, 0, 255}};
  const auto cloud = ToCloud(points, &colours, "map", ros::Time(1));
  ASSERT_EQ(cloud.width, 2u);
  ASSERT_EQ(cloud.point_step, 16u);
  float xyz[3];
  std::memcpy(xyz, &cloud.data[16], 12);
  EXPECT_EQ(xyz[1], 5.f);
  std::uint32_t rgb = 0;
  std::memcpy(&rgb, &cloud.data[12], 4);
  EXPECT_EQ(rgb, 0xFF0000u);

  ObjectEstimate chair;
  chair.id = 7, chair.class_name = "chair", chair.confidence = 0.834, chair.exported = true;
  chair.class_share = 0.75, chair.observations = 5;
  chair.centroid = {0, 0, 2}, chair.size = {0.5, 1, 0.5};
  ObjectEstimate unsure = chair;
  unsure.exported = false;
  const auto markers = ObjectMarkers({chair, unsure}, "map", ros::Time(1));
  ASSERT_EQ(markers.markers.size(), 3u);  // DELETEALL, the box, its label: the unexported one is not shown
  EXPECT_EQ(markers.markers[0].action, visualization_msgs::Marker::DELETEALL);
  EXPECT_EQ(markers.markers[1].points.size(), 24u);  // 12 edges
  EXPECT_EQ(markers.markers[2].text, "chair 75% \u00b7 5 views");

  const auto cells = CellMarker({{0, 0, 1, 0.05f}, {0, -1, 1, 0.05f}}, "map", ros::Time(1));
  ASSERT_EQ(cells.points.size(), 2u);
  ASSERT_EQ(cells.colors.size(), 2u);
  EXPECT_LT(cells.colors[0].r, cells.colors[1].r);  // the higher cell (up is -y) is redder
  EXPECT_FLOAT_EQ(static_cast<float>(cells.scale.x), 0.05f);

  FrameSnapshot frame;
  frame.bgr = cv::Mat(48, 64, CV_8UC3, cv::Scalar(0, 0, 0));
  frame.keypoints = {{10, 10}, {30, 30}};
  frame.labels = {FrameSnapshot::kKept, FrameSnapshot::kRejected};
  Detection person;
  person.class_name = "person", person.score = 0.9f, person.box = cv::Rect2f(20, 20, 20, 20);
  frame.detections = {person};
  const auto image = AnnotatedImage(frame, "camera");
  EXPECT_EQ(image.width, 64u);
  EXPECT_EQ(image.encoding, "bgr8");
  EXPECT_EQ(image.data.size(), 64u * 48u * 3u);
  const cv::Mat drawn(48, 64, CV_8UC3, const_cast<std::uint8_t*>(image.data.data()));
  EXPECT_GT(drawn.at<cv::Vec3b>(10, 13)[1], 100);  // the kept keypoint's green circle
}

TEST(RosOutputs, MoverMarkersWithTrails) {
  MoverSnapshot walker;
  walker.id = 3, walker.class_name = "person", walker.state = movers::TrackState::kConfirmed;
  walker.extent = {0.4, 1.6, 0.3};
  MoverSnapshot box = walker;
  box.id = 4, box.class_name = "unknown", box.state = movers::TrackState::kLost;
  MoverSnapshot sitting = walker;
  sitting.id = 5, sitting.state = movers::TrackState::kTentative;
  MoverTrails trails;
  for (int i = 0; i <= 40; ++i) {  // 4 s at 10 Hz, walking along x
    walker.position = {0.1 * i, 0, 2};
    trails.Update({walker, box, sitting}, FromSeconds(0.1 * i));
  }
  ASSERT_NE(trails.Of(3), nullptr);
  EXPECT_EQ(trails.Of(3)->size(), 31u);  // the last 3 s
  EXPECT_DOUBLE_EQ(trails.Of(3)->front().second.x(), 1.0);
  EXPECT_EQ(trails.Of(5)->size(), 31u);  // a tentative track's path is kept for when it is confirmed

  const auto markers = MoverMarkers({walker, box, sitting}, trails, "map", ros::Time(4));
  ASSERT_EQ(markers.markers.size(), 7u);  // DELETEALL, then a box, a label and a trail per shown track
  EXPECT_EQ(markers.markers[0].action, visualization_msgs::Marker::DELETEALL);
  const auto& walker_box = markers.markers[1];
  EXPECT_EQ(walker_box.header.frame_id, "map");
  EXPECT_EQ(walker_box.type, visualization_msgs::Marker::LINE_LIST);
  EXPECT_EQ(walker_box.id, 3);
  ASSERT_EQ(walker_box.points.size(), 24u);  // 12 edges around (4, 0, 2)
  for (const auto& p : walker_box.points) {
    EXPECT_NEAR(std::abs(p.x - 4.0), 0.2, 1e-9);
    EXPECT_NEAR(std::abs(p.y), 0.8, 1e-9);
  }
  EXPECT_EQ(markers.markers[2].type, visualization_msgs::Marker::TEXT_VIEW_FACING);
  EXPECT_EQ(markers.markers[2].text, "3 person");
  EXPECT_LT(markers.markers[2].pose.position.y, -0.8);  // above the box: up is -y
  EXPECT_EQ(markers.markers[3].type, visualization_msgs::Marker::LINE_STRIP);
  EXPECT_EQ(markers.markers[3].points.size(), 31u);
  EXPECT_DOUBLE_EQ(markers.markers[3].points.back().x, 4.0);
  EXPECT_EQ(markers.markers[5].text, "4 unknown (lost)");
  EXPECT_NE(markers.markers[4].color.r, walker_box.color.r);  // a colour per id
  EXPECT_LT(markers.markers[4].color.a, walker_box.color.a);  // lost: dimmer

  trails.Update({walker}, FromSeconds(4.1));  // the others are gone: so are their trails
  EXPECT_EQ(trails.Of(4), nullptr);
  EXPECT_EQ(trails.Of(5), nullptr);
  EXPECT_EQ(MoverMarkers({}, trails, "map", ros::Time(5)).markers.size(), 1u);  // DELETEALL alone
}

}  // namespace
}  // namespace sgslam::ros_bridge
