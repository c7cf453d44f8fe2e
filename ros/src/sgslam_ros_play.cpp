// sgslam_ros_play: a TUM-layout folder (a TUM RGB-D or Bonn sequence, or `sgslam
// synth` output) as the topics of an RGB-D camera driver, published at the pace of
// its own timestamps (times --rate), or written to a bag that `rosbag play` takes.
//   sgslam_ros_play FOLDER [--rate R] [--depth-encoding 32FC1|16UC1] [--bag OUT.bag] ...
// The colour image goes out at its timestamp, the depth image at its own, and the
// camera_info (from the folder's configuration, as `sgslam run` reads it) with the
// colour image.
#include <chrono>
#include <csignal>
#include <sys/wait.h>
#include <cstdio>
#include <limits>
#include <vector>
#include <filesystem>
#include <optional>
#include <string>
#include <thread>

#include <CLI/CLI.hpp>
#include <ros/ros.h>
#include <fmt/format.h>
#include <ros/serialization.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/image_encodings.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "ros_messages.h"
#include "sgslam/common/data_dir.h"
#include "sgslam/common/error.h"
#include "sgslam/io/atomic_write.h"
#include "sgslam/io/frame_stream.h"
#include "sgslam/io/output_plan.h"
#include "sgslam/io/tum_dataset.h"
#include "sgslam/system/run_config.h"

namespace {

namespace fs = std::filesystem;
using sgslam::ros_bridge::ToImage;
using sgslam::ros_bridge::ToRosTime;

struct PlayOptions {
  std::string folder, config, bag, depth_encoding = "32FC1";
  std::string rgb_topic = "/camera/rgb/image_color", depth_topic = "/camera/depth/image";
  std::string info_topic = "/camera/rgb/camera_info", frame_id = "camera";
  double rate = 1.0, wait_subscribers = 0.0;
  std::size_t max_frames = 0;
  bool now = false, no_camera_info = false;
};

// Raw depth (camera.depth_factor per metre) in the chosen encoding.
sensor_msgs::Image DepthMessage(const cv::Mat& raw, double depth_factor, const std::string& encoding,
                                const ros::Time& stamp, const std::string& frame_id) {
  cv::Mat out;
  if (encoding == "32FC1") {
    raw.convertTo(out, CV_32FC1, 1.0 / depth_factor);
    out.setTo(std::numeric_limits<float>::quiet_NaN(), raw == 0);  // as the TUM bags: no depth is NaN
  } else {
    raw.convertTo(out, CV_16UC1, 1000.0 / depth_factor);  // millimetres, rounded
  }
  return ToImage(out, encoding, stamp, frame_id);
}

sensor_msgs::CameraInfo InfoMessage(const sgslam::CameraConfig& c, const ros::Time& stamp, const std::string& frame_id) {
  sensor_msgs::CameraInfo info;
  info.header.stamp = stamp;
  info.header.frame_id = frame_id;
  info.width = static_cast<std::uint32_t>(c.width);
  info.height = static_cast<std::uint32_t>(c.height);
  info.distortion_model = "plumb_bob";
  info.D = {c.k1, c.k2, c.p1, c.p2, c.k3};
  info.K = {c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1};
  info.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  info.P = {c.fx, 0, c.cx, 0, 0, c.fy, c.cy, 0, 0, 0, 1, 0};
  return info;
}

// The bag neither among the sequence's files nor over a file of another kind
// (io/output_plan.h); the temporary files of a killed writer cleared away.
void CheckBag(const PlayOptions& o) {
  sgslam::OutputPlan plan;
  plan.ReadsFolder(o.folder, "the sequence folder");
  if (!o.config.empty()) plan.Reads(sgslam::ResolveConfigPath(o.config), "the configuration file given with --config");
  plan.Writes(o.bag, "--bag", "#ROSBAG V2.0");
  plan.Check();
  sgslam::RemoveStaleTempFiles(o.bag);
}

// One frame's messages, to the topics or the bag.
class Sink {
 public:
  virtual ~Sink() = default;
  virtual void Write(const std::string& topic, const ros::Time& t, const sensor_msgs::Image& m) = 0;
  virtual void Write(const std::string& topic, const ros::Time& t, const sensor_msgs::CameraInfo& m) = 0;
};

// text as one shell word.
std::string Quoted(const std::string& text) {
  std::string q = "'";
  for (char c : text) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// A bag, written by Debian's Python rosbag (its C++ rosbag needs the ROS 2
// class_loader Debian ships): the messages go serialized down a pipe to
// bag_writer.py, which writes them to a temporary file and renames it at the end.
class BagSink : public Sink {
 public:
  explicit BagSink(const fs::path& bag) {
    const auto data = sgslam::DataDir();
    const fs::path writer = data ? *data / "ros" / "bag_writer.py" : fs::path();
    if (!data || !fs::is_regular_file(writer)) {
      throw sgslam::InputError("the bag writer (share/sgslam/ros/bag_writer.py) was not found beside the executable");
    }
    const std::string command = "/usr/bin/python3 " + Quoted(writer.string()) + " " + Quoted(bag.string()) + " " +
                                Quoted(sgslam::TempFilePrefix(bag));
    std::signal(SIGPIPE, SIG_IGN);  // a writer that died: a write error, reported, not a silent end
    pipe_ = popen(command.c_str(), "w");
    if (!pipe_) throw sgslam::InputError("cannot start " + command);
  }
  ~BagSink() override {
    if (pipe_) pclose(pipe_);
  }
  void Write(const std::string& topic, const ros::Time& t, const sensor_msgs::Image& m) override { Send(topic, t, m); }
  void Write(const std::string& topic, const ros::Time& t, const sensor_msgs::CameraInfo& m) override {
    Send(topic, t, m);
  }
  // Ends the stream and waits for the writer, which renames the bag into place only
  // now; throws when it failed (it said why on stderr). Without Close (an error
  // before the end), the writer leaves no bag.
  void Close() {
    const bool ended = std::fputs("END\n", pipe_) >= 0;
    const int status = pclose(std::exchange(pipe_, nullptr));
    if (!ended || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
      throw sgslam::InputError("the bag writer failed (see its message above)");
    }
  }

 private:
  template <typename M>
  void Send(const std::string& topic, const ros::Time& t, const M& m) {
    const std::uint32_t n = ros::serialization::serializationLength(m);
    std::vector<std::uint8_t> buffer(n);
    ros::serialization::OStream stream(buffer.data(), n);
    ros::serialization::serialize(stream, m);
    const std::string header = fmt::format("{} {} {} {} {} {}\n", topic, ros::message_traits::datatype(m),
                                           ros::message_traits::md5sum(m), t.sec, t.nsec, n);
    if (std::fwrite(header.data(), 1, header.size(), pipe_) != header.size() ||
        std::fwrite(buffer.data(), 1, n, pipe_) != n) {
      throw sgslam::InputError("the bag writer stopped taking messages (see its error above)");
    }
  }
  FILE* pipe_ = nullptr;
};

class TopicSink : public Sink {
 public:
  TopicSink(ros::NodeHandle& nh, const PlayOptions& o)
      : rgb_(nh.advertise<sensor_msgs::Image>(o.rgb_topic, 5)),
        depth_(nh.advertise<sensor_msgs::Image>(o.depth_topic, 5)),
        info_(nh.advertise<sensor_msgs::CameraInfo>(o.info_topic, 5)),
        o_(o) {}
  void Write(const std::string& topic, const ros::Time&, const sensor_msgs::Image& m) override {
    (topic == o_.rgb_topic ? rgb_ : depth_).publish(m);
  }
  void Write(const std::string&, const ros::Time&, const sensor_msgs::CameraInfo& m) override { info_.publish(m); }
  // Waits up to `seconds` for a subscriber to every image topic.
  void WaitForSubscribers(double seconds) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (ros::ok() && std::chrono::steady_clock::now() < until &&
           (rgb_.getNumSubscribers() == 0 || depth_.getNumSubscribers() == 0)) {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  }

 private:
  ros::Publisher rgb_, depth_, info_;
  const PlayOptions& o_;
};

// Every frame to sink; with pace, each at the time of its colour timestamp (from the
// first frame's, divided by rate). Returns the frames written; *late: how many went
// out more than 10 ms after their time (the machine was busy).
std::size_t Play(const PlayOptions& o, Sink& sink, bool pace, std::size_t* late_out = nullptr) {
  std::size_t late = 0;
  const sgslam::RunConfig rc = sgslam::ResolveRunConfig(
      o.config.empty() ? std::nullopt : std::optional<fs::path>(o.config), o.folder);
  const sgslam::TumDataset dataset(o.folder, rc.config.dataset);
  const sgslam::CameraConfig& camera = rc.config.camera;
  sgslam::FrameStream stream(dataset, camera, 4, o.max_frames);
  const auto start = std::chrono::steady_clock::now();
  const sgslam::Timestamp t0 = dataset.frames().front().t_rgb;
  std::size_t n = 0;
  while (auto frame = stream.Next()) {
    if (pace) {
      const auto due = start + std::chrono::nanoseconds(static_cast<std::int64_t>((frame->t - t0) / o.rate));
      std::this_thread::sleep_until(due);
      if (!ros::ok()) break;
      late += std::chrono::steady_clock::now() - due > std::chrono::milliseconds(10);
    }
    const sgslam::FrameRecord& rec = dataset.frames()[frame->index];
    const ros::Time now = ros::Time::now();
    const ros::Time t_rgb = o.now ? now : ToRosTime(rec.t_rgb);
    const ros::Time t_depth = o.now ? now + ros::Duration(sgslam::ToSeconds(rec.t_depth - rec.t_rgb)) : ToRosTime(rec.t_depth);
    sink.Write(o.rgb_topic, t_rgb, ToImage(frame->bgr, sensor_msgs::image_encodings::BGR8, t_rgb, o.frame_id));
    if (!o.no_camera_info) sink.Write(o.info_topic, t_rgb, InfoMessage(camera, t_rgb, o.frame_id));
    sink.Write(o.depth_topic, t_depth, DepthMessage(frame->depth, camera.depth_factor, o.depth_encoding, t_depth, o.frame_id));
    ++n;
  }
  if (late_out) *late_out = late;
  return n;
}

}  // namespace

int main(int argc, char** argv) {
  // Logs to stderr, as sgslam's (roscpp's own go to stdout and rosout).
  spdlog::set_default_logger(spdlog::stderr_color_mt("sgslam"));
  spdlog::set_pattern("[%l] %v");
  PlayOptions o;
  CLI::App app{"Publishes a TUM-layout RGB-D folder as a camera's ROS topics at its timestamps, or writes it to a bag"};
  app.add_option("folder", o.folder, "the sequence (rgb.txt, depth.txt, images)")->required()->check(CLI::ExistingDirectory);
  app.add_option("--config", o.config, "the camera configuration, as `sgslam run --config` (default: the folder's)");
  app.add_option("--rate", o.rate, "times the camera's rate")->check(CLI::Range(0.01, 100.0));
  app.add_option("--depth-encoding", o.depth_encoding, "32FC1 (metres, as the TUM bags) or 16UC1 (millimetres)")
      ->check(CLI::IsMember({"32FC1", "16UC1"}));
  app.add_option("--max-frames", o.max_frames, "the first N frames only (0: all)");
  app.add_option("--bag", o.bag, "write this bag instead of publishing");
  app.add_option("--wait-subscribers", o.wait_subscribers, "s to wait for a subscriber to both image topics first")
      ->check(CLI::Range(0.0, 3600.0));
  app.add_flag("--now", o.now, "stamp the messages with the time they are sent, not the dataset's");
  app.add_flag("--no-camera-info", o.no_camera_info, "publish no camera_info");
  app.add_option("--rgb-topic", o.rgb_topic);
  app.add_option("--depth-topic", o.depth_topic);
  app.add_option("--camera-info-topic", o.info_topic);
  app.add_option("--frame-id", o.frame_id, "the images' frame_id");
  // ROS's own arguments (remappings such as __name:=play or /camera/rgb/image_color:=/rgb) go to ros::init.
  std::vector<char*> ros_argv{argv[0]}, cli_argv{argv[0]};
  for (int i = 1; i < argc; ++i) (std::string(argv[i]).find(":=") != std::string::npos ? ros_argv : cli_argv).push_back(argv[i]);
  int cli_argc = static_cast<int>(cli_argv.size()), ros_argc = static_cast<int>(ros_argv.size());
  CLI11_PARSE(app, cli_argc, cli_argv.data());
  try {
    if (!o.bag.empty()) {
      CheckBag(o);
      ros::Time::init();
      BagSink bag(o.bag);
      const std::size_t n = Play(o, bag, false);
      bag.Close();
      spdlog::info("{} frames written to {}", n, o.bag);
      return 0;
    }
    ros::init(ros_argc, ros_argv.data(), "sgslam_play", ros::init_options::AnonymousName);
    ros::NodeHandle nh;
    TopicSink topics(nh, o);
    if (o.wait_subscribers > 0) topics.WaitForSubscribers(o.wait_subscribers);
    std::size_t late = 0;
    const std::size_t n = Play(o, topics, true, &late);
    ros::Duration(0.5).sleep();  // let the last messages go out
    spdlog::info("{} frames published from {} ({} of them more than 10 ms late)", n, o.folder, late);
    return ros::ok() ? 0 : 130;
  } catch (const std::exception& e) {
    spdlog::error("sgslam_ros_play: {}", e.what());
    return 1;
  }
}
