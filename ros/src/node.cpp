#include "node.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "ros_messages.h"
#include "sgslam/common/error.h"

namespace sgslam::ros_bridge {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

template <typename T>
T Param(const ros::NodeHandle& nh, const std::string& name, T fallback) {
  T value = fallback;
  nh.param<T>(name, value, fallback);
  return value;
}

// Above the map frame (the first camera's: x right, y down, z forward): z up, x
// forward, as Rviz and robots expect.
SE3 WorldFromMap() {
  Eigen::Matrix3d R;
  R << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  return SE3(R, Eigen::Vector3d::Zero());
}

}  // namespace

NodeOptions ReadNodeOptions(const ros::NodeHandle& p) {
  NodeOptions o;
  o.rgb_topic = Param(p, "rgb_topic", o.rgb_topic);
  o.depth_topic = Param(p, "depth_topic", o.depth_topic);
  o.info_topic = Param(p, "camera_info_topic", o.info_topic);
  o.config = Param(p, "config", o.config);
  o.mode = Param(p, "mode", o.mode);
  o.model = Param(p, "model", o.model);
  o.out = Param(p, "out", o.out);
  o.sequential = Param(p, "sequential", o.sequential);
  o.use_camera_info = Param(p, "use_camera_info", o.use_camera_info);
  o.camera_info_wait = Param(p, "camera_info_wait", o.camera_info_wait);
  o.queue_size = Param(p, "queue_size", o.queue_size);
  o.sync_queue = Param(p, "sync_queue", o.sync_queue);
  o.map_frame = Param(p, "map_frame", o.map_frame);
  o.camera_frame = Param(p, "camera_frame", o.camera_frame);
  o.world_frame = Param(p, "world_frame", o.world_frame);
  o.map_period = Param(p, "map_period", o.map_period);
  o.mcap = Param(p, "mcap", o.mcap);
  const auto check = [](bool ok, const std::string& what) {
    if (!ok) throw ConfigError("parameter ~" + what);
  };
  check(o.queue_size >= 1 && o.queue_size <= 100, fmt::format("queue_size {} is not in [1, 100]", o.queue_size));
  check(o.sync_queue >= 1 && o.sync_queue <= 1000, fmt::format("sync_queue {} is not in [1, 1000]", o.sync_queue));
  check(std::isfinite(o.camera_info_wait) && o.camera_info_wait >= 0 && o.camera_info_wait <= 3600,
        fmt::format("camera_info_wait {} is not in [0, 3600] s", o.camera_info_wait));
  check(std::isfinite(o.map_period) && o.map_period >= 0 && o.map_period <= 3600,
        fmt::format("map_period {} is not in [0, 3600] s", o.map_period));
  check(!o.map_frame.empty() && !o.camera_frame.empty(), "map_frame and camera_frame must not be empty");
  check(o.map_frame != o.camera_frame && o.world_frame != o.map_frame && o.world_frame != o.camera_frame,
        "world_frame, map_frame and camera_frame must differ");
  check(!o.rgb_topic.empty() && !o.depth_topic.empty(), "rgb_topic and depth_topic must not be empty");
  return o;
}

SlamNode::SlamNode(ros::NodeHandle& nh, ros::NodeHandle& private_nh, NodeOptions options)
    : options_(std::move(options)), nh_(nh), queue_(static_cast<std::size_t>(options_.queue_size), Overflow::kDropOldest) {
  config_ = LoadNodeConfig(options_.config, options_.mode, options_.model);
  detector_ = LoadNodeDetector(config_);
  out_ = options_.out;
  CheckNodeOutputs(config_, out_, options_.mcap);
  std::error_code ec;
  fs::create_directories(out_, ec);
  if (!fs::is_directory(out_, ec)) throw InputError("cannot create output folder " + out_.string() + " (~out)");
  WriteConfigUsed(config_.config, config_.source, out_);
  odom_pub_ = private_nh.advertise<nav_msgs::Odometry>("odometry", 10);
  path_pub_ = private_nh.advertise<nav_msgs::Path>("path", 1, true);
  points_pub_ = private_nh.advertise<sensor_msgs::PointCloud2>("map_points", 1, true);
  cloud_pub_ = private_nh.advertise<sensor_msgs::PointCloud2>("cloud", 1, true);
  objects_pub_ = private_nh.advertise<visualization_msgs::MarkerArray>("objects", 1, true);
  cells_pub_ = private_nh.advertise<visualization_msgs::Marker>("octomap_cells", 1, true);
  movers_pub_ = private_nh.advertise<visualization_msgs::MarkerArray>("movers", 10);
  image_pub_ = private_nh.advertise<sensor_msgs::Image>("image", 2);
  save_srv_ = private_nh.advertiseService("save", &SlamNode::OnSave, this);
  if (!options_.world_frame.empty()) {
    static_tf_.sendTransform(ToTransform(WorldFromMap(), options_.world_frame, options_.map_frame, ros::Time(0)));
  }
  path_.header.frame_id = options_.map_frame;
  if (options_.use_camera_info && !options_.info_topic.empty()) {
    info_sub_ = nh_.subscribe(options_.info_topic, 2, &SlamNode::OnCameraInfo, this);
    use_info_ = true;
  }
  // TCP_NODELAY: with Nagle's algorithm the tail of each image waits for the ACK.
  const ros::TransportHints hints = ros::TransportHints().tcpNoDelay();
  rgb_sub_.subscribe(nh_, options_.rgb_topic, static_cast<std::uint32_t>(options_.sync_queue), hints);
  depth_sub_.subscribe(nh_, options_.depth_topic, static_cast<std::uint32_t>(options_.sync_queue), hints);
  // The policy holds a pair until it can prove no later message pairs better. A
  // lower bound on the interval between a topic's messages proves it at once for
  // pairs stamped up to about half a frame apart (RealSense's aligned depth: 0);
  // without it every pair waited for the next frame (fr1_rpy: 73 ms from message
  // time to pose, not 36; docs/results.md).
  sync_ = std::make_unique<message_filters::Synchronizer<Policy>>(Policy(static_cast<std::uint32_t>(options_.sync_queue)),
                                                                   rgb_sub_, depth_sub_);
  sync_->setInterMessageLowerBound(ros::Duration(0.9 / config_.config.camera.fps));
  sync_->registerCallback(&SlamNode::OnImages, this);
  worker_ = std::thread([this] { Work(); });  // last: a constructor that throws has no thread to join
  spdlog::info("sgslam_ros: mode {}, config {}; listening to {} and {}{}; outputs in {}", config_.config.dynamic.mode,
               config_.source, options_.rgb_topic, options_.depth_topic,
               use_info_ ? " (camera from " + options_.info_topic + ")" : std::string(" (camera from the config)"),
               out_.string());
}

SlamNode::~SlamNode() {
  stop_ = true;
  queue_.Shutdown();
  if (worker_.joinable()) worker_.join();
}

void SlamNode::OnCameraInfo(const sensor_msgs::CameraInfoConstPtr& info) {
  const std::lock_guard lock(camera_mutex_);
  if (!info_) info_ = *info;
}

// Why a frame's stamp is refused: not after the last one taken (a duplicate or one
// out of order: tracking needs time to go forward), or empty. Tells of a gap.
std::string SlamNode::CheckStamp(Timestamp t) {
  if (last_t_ && t <= *last_t_) {
    return fmt::format("its stamp is {} the last frame's ({:.6f})", t == *last_t_ ? "the same as" : "before",
                       ToSeconds(*last_t_));
  }
  if (last_t_ && t - *last_t_ > FromSeconds(1.0)) {
    ROS_WARN("sgslam_ros: images resumed after a gap of %.1f s in their stamps", ToSeconds(t - *last_t_));
  }
  last_t_ = t;
  return {};
}

// The camera, fixed at the first frame taken: camera_info's when it has come (and
// is usable), else, after camera_info_wait, the config's. False: wait longer.
bool SlamNode::ChooseCamera(Timestamp t) {
  if (camera_) return true;
  std::optional<sensor_msgs::CameraInfo> info;
  {
    const std::lock_guard lock(camera_mutex_);
    info = info_;
  }
  if (!first_image_t_) first_image_t_ = t;
  if (use_info_ && !info && t - *first_image_t_ < FromSeconds(options_.camera_info_wait)) {
    ++rejected_input_;  // waiting for camera_info: counted with the refused
    return false;
  }
  CameraConfig camera = config_.config.camera;
  if (info) {
    std::string error;
    std::optional<CameraConfig> c = CameraFromInfo(*info, config_.config.camera, &error);
    if (c) {
      try {
        Config check = config_.config;
        check.camera = *c;
        check.Validate(options_.info_topic);
      } catch (const std::exception& e) {
        error = e.what();
        c.reset();
      }
    }
    if (c) {
      camera = *c;
      config_.source += " + the camera of " + options_.info_topic;
      ROS_INFO("sgslam_ros: camera from %s: %dx%d fx %.1f fy %.1f cx %.1f cy %.1f", options_.info_topic.c_str(),
               camera.width, camera.height, camera.fx, camera.fy, camera.cx, camera.cy);
    } else {
      ROS_ERROR("sgslam_ros: %s; using the config's camera (%s)", error.c_str(), config_.source.c_str());
    }
  } else if (use_info_) {
    ROS_WARN("sgslam_ros: no camera_info on %s within %.1f s of the first images: using the config's camera (%s)",
             options_.info_topic.c_str(), options_.camera_info_wait, config_.source.c_str());
  }
  config_.config.camera = camera;
  camera_ = camera;
  return true;
}

// roscpp does not catch what a callback throws: nothing may leave it.
void SlamNode::OnImages(const sensor_msgs::ImageConstPtr& rgb, const sensor_msgs::ImageConstPtr& depth) {
  try {
    TakeImages(*rgb, *depth);
  } catch (const std::exception& e) {
    ++rejected_input_;
    ROS_ERROR("sgslam_ros: frame %.6f skipped: %s", rgb->header.stamp.toSec(), e.what());
  }
}

void SlamNode::TakeImages(const sensor_msgs::Image& rgb, const sensor_msgs::Image& depth) {
  const Clock::time_point arrival = Clock::now();
  const Timestamp t = FromRosTime(rgb.header.stamp);
  // A frame refused: logged when the kind of problem changes, not every frame.
  const auto refuse = [&](const char* kind, const std::string& error) {
    ++rejected_input_;
    if (kind != last_input_error_) {
      ROS_ERROR("sgslam_ros: frame %.6f skipped: %s (%zu frames refused so far)", ToSeconds(t), error.c_str(),
                rejected_input_.load());
      last_input_error_ = kind;
    }
  };
  if (!ChooseCamera(t)) return;
  Converted colour = ColourToBgr(rgb);
  if (!colour.error.empty()) return refuse("colour", colour.error);
  Converted raw = DepthToRaw(depth, camera_->depth_factor);
  if (!raw.error.empty()) return refuse("depth", raw.error);
  if (colour.image.size() != raw.image.size()) {
    return refuse("sizes", fmt::format("colour image {}x{} and depth image {}x{} differ in size", colour.image.cols,
                                       colour.image.rows, raw.image.cols, raw.image.rows));
  }
  if (colour.image.cols != camera_->width || colour.image.rows != camera_->height) {
    return refuse("camera", fmt::format("images are {}x{}, the camera is {}x{}", colour.image.cols,
                                        colour.image.rows, camera_->width, camera_->height));
  }
  if (const std::string error = CheckStamp(t); !error.empty()) return refuse("stamp", error);
  if (!last_input_error_.empty()) {
    ROS_INFO("sgslam_ros: frames are usable again");
    last_input_error_.clear();
  }
  Pending p;
  p.images.index = index_++;
  p.images.t = t;
  p.images.bgr = colour.image;
  p.images.depth = raw.image;
  p.arrival = arrival;
  queue_.Push(std::move(p));
}

bool SlamNode::OnSave(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  std::future<std::string> done;
  {
    const std::lock_guard lock(save_mutex_);
    if (closing_ || save_request_) {
      res.success = false;
      res.message = closing_ ? "the node is stopping: it writes every output itself" : "a save is already under way";
      return true;
    }
    save_request_.emplace();
    done = save_request_->get_future();
  }
  queue_.Wake();
  if (done.wait_for(std::chrono::seconds(60)) != std::future_status::ready) {
    res.success = false;
    res.message = "the tracking thread did not answer within 60 s";
    return true;
  }
  res.message = done.get();
  res.success = res.message.rfind("written", 0) == 0;
  return true;
}

void SlamNode::Work() {
  while (!stop_) {
    std::optional<Pending> frame = queue_.PopFor(std::chrono::milliseconds(200));
    AnswerSave();
    if (frame && failure_.empty()) {
      try {
        ProcessFrame(*frame);
      } catch (const std::exception& e) {
        failure_ = processed_ == 0 ? e.what() : fmt::format("frame {}: {}", frame->images.index, e.what());
        ROS_ERROR("sgslam_ros: tracking stopped: %s (the outputs of the frames before are written at the end)",
                  failure_.c_str());
      }
    } else if (!frame && queue_.shut_down()) {
      break;
    }
    if (runner_) {
      try {
        PublishMaps(false);
      } catch (const std::exception& e) {
        ROS_ERROR_THROTTLE(10.0, "sgslam_ros: maps not published: %s", e.what());
      }
    }
  }
  AnswerSave();
}

void SlamNode::AnswerSave() {
  const std::lock_guard lock(save_mutex_);
  if (!save_request_) return;
  std::string answer = "nothing to save: no frame has been processed yet";
  try {
    if (runner_) answer = runner_->SaveNow();
  } catch (const std::exception& e) {
    answer = std::string("not written: ") + e.what();
  }
  save_request_->set_value(answer);
  save_request_.reset();
}

void SlamNode::ProcessFrame(Pending& frame) {
  if (!runner_) {
    WriteConfigUsed(config_.config, config_.source, out_);  // with the camera chosen at the first frame
    runner_ = std::make_unique<SlamRunner>(config_.config, options_.sequential, std::move(detector_), out_, options_.mcap);
    ROS_INFO("sgslam_ros: system started, mode %s, detector: %s", config_.config.dynamic.mode.c_str(),
             runner_->DescribeDetector().c_str());
    last_maps_ = Clock::now();
  }
  const std::shared_ptr<const FrameSnapshot> snapshot = runner_->Process(frame.images);
  if (snapshot) PublishFrame(*snapshot);
  latency_ms_.push_back(std::chrono::duration<double, std::milli>(Clock::now() - frame.arrival).count());
  ++processed_;
}

void SlamNode::PublishFrame(const FrameSnapshot& f) {
  const ros::Time stamp = ToRosTime(f.t);
  if (f.T_w_c) {
    tf_.sendTransform(ToTransform(*f.T_w_c, options_.map_frame, options_.camera_frame, stamp));
    const nav_msgs::Odometry odom = ToOdometry(*f.T_w_c, options_.map_frame, options_.camera_frame, stamp);
    odom_pub_.publish(odom);
    geometry_msgs::PoseStamped pose;
    pose.header = odom.header;
    pose.pose = odom.pose.pose;
    path_.poses.push_back(pose);
    path_.header.stamp = stamp;
    // The whole path at most every map_period: it grows with the run.
    const auto period = std::chrono::duration<double>(options_.map_period);
    if (path_pub_.getNumSubscribers() > 0 && Clock::now() - last_path_ >= period) {
      path_pub_.publish(path_);
      last_path_ = Clock::now();
    }
  }
  // A frame without a pose has no tracks: their trails wait for the next one. Its
  // markers, the DELETEALL alone, clear the tracks, whose place is not known then.
  if (f.T_w_c) trails_.Update(f.movers, f.t);
  if (movers_pub_.getNumSubscribers() > 0) {
    movers_pub_.publish(MoverMarkers(f.movers, trails_, options_.map_frame, stamp));
  }
  if (image_pub_.getNumSubscribers() > 0 && !f.bgr.empty()) image_pub_.publish(AnnotatedImage(f, options_.camera_frame));
}

// The sparse map, the dense cloud, the objects and the OctoMap's cells, at most
// every map_period, when they changed: a new keyframe, or the semantic thread's
// cloud or cells (it follows tracking by a few keyframes). force: now, as they are.
void SlamNode::PublishMaps(bool force) {
  if (!force && Clock::now() - last_maps_ < std::chrono::duration<double>(options_.map_period)) return;
  last_maps_ = Clock::now();
  const MapSnapshot map = runner_->SnapshotMap();
  if (!force && map.keyframes.size() == published_keyframes_ && map.cloud.size() == published_pieces_ &&
      map.cells.get() == published_cells_) {
    return;
  }
  published_keyframes_ = map.keyframes.size();
  published_pieces_ = map.cloud.size();
  published_cells_ = map.cells.get();
  const ros::Time stamp = ros::Time::now();
  std::vector<Eigen::Vector3f> points;
  points.reserve(map.points.size());
  for (const Eigen::Vector3d& p : map.points) points.push_back(p.cast<float>());
  points_pub_.publish(ToCloud(points, nullptr, options_.map_frame, stamp));
  if (!runner_->semantic()) return;
  cloud_pub_.publish(DenseCloud(map, options_.map_frame, stamp));
  objects_pub_.publish(ObjectMarkers(map.objects, options_.map_frame, stamp));
  if (map.cells) cells_pub_.publish(CellMarker(*map.cells, options_.map_frame, stamp));
}

bool SlamNode::Finish(const std::string& ended) {
  if (finished_) return true;
  finished_ = true;
  {
    const std::lock_guard lock(save_mutex_);
    closing_ = true;  // a save asked from now on is refused, not left waiting
  }
  save_srv_.shutdown();
  rgb_sub_.unsubscribe();
  depth_sub_.unsubscribe();
  queue_.Shutdown();
  if (worker_.joinable()) worker_.join();  // takes the frames already queued, answers a save under way
  LiveStats live;
  live.topics = {options_.rgb_topic, options_.depth_topic};
  live.dropped = queue_.dropped();
  live.refused = rejected_input_;
  live.latency_ms = latency_ms_;
  bool written = true;
  if (runner_) {
    try {
      written = runner_->Finish(ended, failure_, live);
    } catch (const std::exception& e) {
      spdlog::error("sgslam_ros: the outputs not written: {}", e.what());
      written = false;
    }
    try {  // the maps after the last bundle adjustment, and the whole path, latched for a late Rviz
      PublishMaps(true);
      path_pub_.publish(path_);
    } catch (const std::exception& e) {
      spdlog::error("sgslam_ros: the final maps not published: {}", e.what());
    }
  } else {
    spdlog::warn("sgslam_ros: no frame was processed: no outputs but config_used.yaml and stats.json");
    try {
      written = WriteStatsWithoutFrames(out_, ended, failure_, live);
    } catch (const std::exception& e) {
      spdlog::error("stats.json not written: {}", e.what());
      written = false;
    }
  }
  spdlog::info("sgslam_ros: {} frames processed, {} dropped (queue full), {} refused (bad input); outputs in {}",
               processed_.load(), live.dropped, live.refused, out_.string());
  return written && failure_.empty();
}

}  // namespace sgslam::ros_bridge
