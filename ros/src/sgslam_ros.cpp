// sgslam_ros: the ROS 1 node (node.h). Runs until Ctrl-C, SIGTERM or SIGHUP (as
// roslaunch sends), or until ROS shuts it down; then writes every output of
// `sgslam run` for the frames processed. Exit status as `sgslam run`'s: 0, or 128 +
// the signal that stopped it, or 1 when an output could not be written or the
// parameters are wrong.
#include <chrono>
#include <exception>
#include <string>

#include <ros/ros.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "node.h"
#include "stop_signals.h"

int main(int argc, char** argv) {
  // Logs to stderr, as sgslam's (roscpp's own go to stdout and rosout).
  spdlog::set_default_logger(spdlog::stderr_color_mt("sgslam"));
  spdlog::set_pattern("[%l] %v");
  // Our own signal handling (stop_signals.h): a stop writes the outputs first.
  ros::init(argc, argv, "sgslam", ros::init_options::NoSigintHandler);
  using sgslam::app::StopSignals;
  const StopSignals signals;
  try {
    ros::NodeHandle nh, private_nh("~");
    sgslam::ros_bridge::SlamNode node(nh, private_nh, sgslam::ros_bridge::ReadNodeOptions(private_nh));
    ros::AsyncSpinner spinner(1);
    spinner.start();
    while (ros::ok() && StopSignals::Received() == 0) {
      StopSignals::WaitUntil(std::chrono::steady_clock::now() + std::chrono::milliseconds(200));
    }
    const int signal = StopSignals::Received();
    const std::string ended = signal ? std::string("interrupted by ") + sgslam::app::SignalName(signal)
                                     : std::string("shut down by ROS");
    ROS_INFO("sgslam_ros: %s: writing the outputs of the %zu frames processed", ended.c_str(), node.frames_processed());
    const bool written = node.Finish(ended);
    spinner.stop();
    ros::shutdown();
    if (!written) return 1;
    return signal ? 128 + signal : 0;
  } catch (const std::exception& e) {
    spdlog::error("sgslam_ros: {}", e.what());
    ros::shutdown();
    return 1;
  }
}
