// The ROS 1 node: colour and depth topics in (synchronised by timestamp), the same
// system as `sgslam run` in the middle, and the pose, maps, objects, mover tracks
// and annotated image out, for Rviz. docs/ros.md is the user's guide.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <filesystem>
#include <future>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <message_filters/subscriber.h>
#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/synchronizer.h>
#include <nav_msgs/Path.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_broadcaster.h>

#include "ros_messages.h"
#include "sgslam/common/bounded_queue.h"
#include "slam_runner.h"

namespace sgslam::ros_bridge {

// The node's parameters (private names, `~rgb_topic` and so on; docs/ros.md).
struct NodeOptions {
  std::string rgb_topic = "/camera/rgb/image_color";
  std::string depth_topic = "/camera/depth/image";
  std::string info_topic = "/camera/rgb/camera_info";
  std::string config;  // a YAML file or a shipped name, as `sgslam run --config`; empty: the TUM fr1 defaults
  std::string mode;    // none, geometric, semantic, sg; empty: the config's
  std::string model;   // detector model folder; empty: the shipped one
  std::string out = "sgslam-out/ros";
  bool sequential = false;
  bool use_camera_info = true;      // intrinsics from camera_info (else the config's camera)
  double camera_info_wait = 1.0;    // s after the first images before falling back to the config's camera
  int queue_size = 2;               // frames waiting for the tracking thread; more: the oldest is dropped
  int sync_queue = 10;              // messages message_filters keeps per topic to pair them
  std::string map_frame = "map";    // the first keyframe's camera (optical) frame
  std::string camera_frame = "camera";
  std::string world_frame = "world";  // z up, x forward, above map (a static transform); empty: none
  double map_period = 1.0;          // s: the maps and objects at most this often (on new keyframes)
  std::string mcap;                 // the run recorded for Foxglove to this MCAP file (docs/foxglove.md); empty: none
};

NodeOptions ReadNodeOptions(const ros::NodeHandle& private_nh);

class SlamNode {
 public:
  SlamNode(ros::NodeHandle& nh, ros::NodeHandle& private_nh, NodeOptions options);
  ~SlamNode();
  SlamNode(const SlamNode&) = delete;
  SlamNode& operator=(const SlamNode&) = delete;

  // Stops taking frames, finishes the system (its last bundle adjustment) and writes
  // every output to options.out; `ended` goes to stats.json. Returns false when an
  // output could not be written (logged).
  bool Finish(const std::string& ended);
  std::size_t frames_processed() const { return processed_; }

 private:
  struct Pending {
    RgbdImages images;
    std::chrono::steady_clock::time_point arrival;
  };
  using Policy = message_filters::sync_policies::ApproximateTime<sensor_msgs::Image, sensor_msgs::Image>;

  void OnImages(const sensor_msgs::ImageConstPtr& rgb, const sensor_msgs::ImageConstPtr& depth);
  void TakeImages(const sensor_msgs::Image& rgb, const sensor_msgs::Image& depth);
  void OnCameraInfo(const sensor_msgs::CameraInfoConstPtr& info);
  std::string CheckStamp(Timestamp t);
  bool ChooseCamera(Timestamp t);
  bool OnSave(std_srvs::Trigger::Request& req, std_srvs::Trigger::Response& res);
  void Work();
  void ProcessFrame(Pending& frame);
  void PublishFrame(const FrameSnapshot& frame);
  void PublishMaps(bool force);
  void AnswerSave();

  NodeOptions options_;
  NodeConfig config_;
  std::unique_ptr<Detector> detector_;  // until the system takes it
  std::filesystem::path out_;

  ros::NodeHandle nh_;
  message_filters::Subscriber<sensor_msgs::Image> rgb_sub_, depth_sub_;
  std::unique_ptr<message_filters::Synchronizer<Policy>> sync_;
  ros::Subscriber info_sub_;
  bool use_info_ = false;  // camera_info subscribed (set before any callback)
  ros::Publisher odom_pub_, path_pub_, points_pub_, cloud_pub_, objects_pub_, cells_pub_, movers_pub_, image_pub_;
  ros::ServiceServer save_srv_;
  tf2_ros::TransformBroadcaster tf_;
  tf2_ros::StaticTransformBroadcaster static_tf_;

  // Callback side (the spinner's thread).
  std::mutex camera_mutex_;
  std::optional<CameraConfig> camera_;     // fixed at the first frame taken
  std::optional<sensor_msgs::CameraInfo> info_;
  std::optional<Timestamp> first_image_t_, last_t_;
  std::size_t index_ = 0;
  std::atomic<std::size_t> rejected_input_{0};  // frames refused: bad encoding, size, stamp (read at the end)
  std::string last_input_error_;  // the kind of the last refusal, until a frame is taken
  BoundedQueue<Pending> queue_;  // Overflow::kDropOldest: the newest frames

  // Tracking side (worker_).
  std::unique_ptr<SlamRunner> runner_;
  std::vector<double> latency_ms_;
  nav_msgs::Path path_;
  MoverTrails trails_;
  // What the maps last published held: they go out again only when this changes.
  std::size_t published_keyframes_ = 0, published_pieces_ = 0;
  const void* published_cells_ = nullptr;
  std::chrono::steady_clock::time_point last_maps_, last_path_;
  std::atomic<std::size_t> processed_{0};
  std::string failure_;  // the error that stopped tracking, if any

  std::mutex save_mutex_;
  std::optional<std::promise<std::string>> save_request_;
  bool closing_ = false;  // under save_mutex_: no save is taken any more
  std::atomic<bool> stop_{false};
  std::thread worker_;
  bool finished_ = false;
};

}  // namespace sgslam::ros_bridge
