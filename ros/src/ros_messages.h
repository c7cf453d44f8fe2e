// Between ROS 1 messages and sgslam's types: the camera's images and calibration in,
// the pose, maps, objects, mover tracks and annotated image out. No node here: these
// functions are tested without a ROS master (ros/tests/ros_messages_test.cpp).
#pragma once

#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Odometry.h>
#include <opencv2/core.hpp>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <visualization_msgs/MarkerArray.h>

#include "sgslam/camera/camera_config.h"
#include "sgslam/common/se3.h"
#include "sgslam/common/time.h"
#include "sgslam/semantic/objects.h"
#include "sgslam/system/mover_trails.h"
#include "sgslam/system/snapshot.h"

namespace sgslam::ros_bridge {

// An image taken from a message, or why it could not be.
struct Converted {
  cv::Mat image;
  std::string error;  // empty when image is set
};

// The colour image as 8-bit BGR (a copy): encodings bgr8, rgb8, bgra8, rgba8, mono8.
Converted ColourToBgr(const sensor_msgs::Image& msg);

// The depth image in RgbdImages' raw units (16-bit, depth_factor per metre): 32FC1
// in metres (the TUM bags; NaN, infinite and <= 0 mean no depth) and 16UC1 or
// mono16 in millimetres (RealSense and Astra drivers; 0 means no depth). A depth past what 16
// bits hold at depth_factor (13.1 m at 5000) becomes 0, no depth.
Converted DepthToRaw(const sensor_msgs::Image& msg, double depth_factor);

// base with the intrinsics and size of info (plumb_bob or rational_polynomial
// distortion, whose first five coefficients are OpenCV's k1 k2 p1 p2 k3; none: no
// distortion); nullopt and *error when info is unusable (zero focal length, no size,
// another distortion model).
std::optional<CameraConfig> CameraFromInfo(const sensor_msgs::CameraInfo& info, const CameraConfig& base,
                                           std::string* error);

ros::Time ToRosTime(Timestamp t);
Timestamp FromRosTime(const ros::Time& t);

// T_w_c as the transform parent -> child (a point in child's frame to parent's).
geometry_msgs::TransformStamped ToTransform(const SE3& T_w_c, const std::string& parent, const std::string& child,
                                            const ros::Time& stamp);
nav_msgs::Odometry ToOdometry(const SE3& T_w_c, const std::string& parent, const std::string& child,
                              const ros::Time& stamp);

// x y z float32 fields, with rgb (packed as PCL's float) when colours is given.
sensor_msgs::PointCloud2 ToCloud(const std::vector<Eigen::Vector3f>& points, const std::vector<Rgb>* colours,
                                 const std::string& frame, const ros::Time& stamp);
// The static dense cloud of a map snapshot: each keyframe's piece placed with its pose.
sensor_msgs::PointCloud2 DenseCloud(const MapSnapshot& map, const std::string& frame, const ros::Time& stamp);

// The exported objects: a wire box and a label ("chair 0.83") each, after a
// DELETEALL so that objects merged away disappear.
visualization_msgs::MarkerArray ObjectMarkers(const std::vector<ObjectEstimate>& objects, const std::string& frame,
                                              const ros::Time& stamp);
// The confirmed and lost mover tracks: a wire box of the extent at the position, an
// "id class" label above it and the trail of its past positions, in a colour per id
// (lost ones dimmer, "(lost)" in the label); after a DELETEALL so that tracks gone
// disappear. Tentative tracks are not shown (new ones, and people sitting still).
visualization_msgs::MarkerArray MoverMarkers(const std::vector<MoverSnapshot>& movers, const MoverTrails& trails,
                                             const std::string& frame, const ros::Time& stamp);
// The OctoMap's occupied cells as one cube list coloured by height (up is -y in the
// map frame, the first camera's).
visualization_msgs::Marker CellMarker(const std::vector<Eigen::Vector4f>& cells, const std::string& frame,
                                      const ros::Time& stamp);

// image (rows copied, no padding) as a message; encoding as sensor_msgs' names it.
sensor_msgs::Image ToImage(const cv::Mat& image, const std::string& encoding, const ros::Time& stamp,
                           const std::string& frame_id);

// The frame with kept keypoints green, rejected red, unjudged yellow, and the
// detection boxes with class and score (carried boxes orange), as bgr8.
sensor_msgs::Image AnnotatedImage(const FrameSnapshot& frame, const std::string& camera_frame);

}  // namespace sgslam::ros_bridge
