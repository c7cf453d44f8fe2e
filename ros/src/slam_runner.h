// The node's SLAM side: the system of `sgslam run`, its frame records and its
// outputs, behind a header with no ROS and no SlamSystem in it. ROS 1's messages
// compile only as C++17 (they use std::allocator<void>::rebind, gone in C++20),
// and the core's headers only as C++20: node.cpp is the former, slam_runner.cpp
// the latter, and this header is both (docs/ros.md).
#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "sgslam/config/config.h"
#include "sgslam/detection/detector.h"
#include "sgslam/io/tum_dataset.h"
#include "sgslam/system/snapshot.h"

namespace sgslam::ros_bridge {

struct NodeConfig {
  Config config;
  std::string source;           // where the values came from, for logs
  std::filesystem::path folder;  // the config file's folder: where detector.backend file finds detections.txt
  std::filesystem::path file;    // the config file read, if any
};

// The configuration: `config` (a file or a shipped name, as `sgslam run --config`)
// over the TUM fr1 camera, then mode and model when not empty; validated.
NodeConfig LoadNodeConfig(const std::string& config, const std::string& mode, const std::string& model);

// The detector of modes semantic and sg (else null), loaded before any frame so
// that a missing model is reported at start.
std::unique_ptr<Detector> LoadNodeDetector(const NodeConfig& config);

// The output folder (~out) and its files, and the recording (~mcap, when not
// empty), checked against the files the node reads (the config, the model, the
// vocabulary), as `sgslam run` checks its own (io/output_plan.h); throws InputError
// naming both paths. Makes the recording's folder.
void CheckNodeOutputs(const NodeConfig& config, const std::filesystem::path& out, const std::string& mcap);

// config_used.yaml in out: `sgslam run`'s writer (apps/run_outputs.h), for node.cpp,
// which cannot include that header.
void WriteConfigUsed(const Config& config, const std::string& source, const std::filesystem::path& out);

// stats.json of a run that processed no frame: how it ended, and why. False when it
// could not be written (logged).
bool WriteStatsWithoutFrames(const std::filesystem::path& out, const std::string& ended, const std::string& failure,
                             const struct LiveStats& live);

// What the node measured of its input, for stats.json's "live" section.
struct LiveStats {
  std::vector<std::string> topics;
  std::size_t dropped = 0, refused = 0;  // queue full; bad input
  std::vector<double> latency_ms;        // arrival of the images to the pose published
};

class SlamRunner {
 public:
  // Starts the system's threads; detector from LoadNodeDetector. mcap: the MCAP file
  // to record the run to (apps/mcap_recorder.h), or empty.
  SlamRunner(const Config& config, bool sequential, std::unique_ptr<Detector> detector, std::filesystem::path out,
             const std::string& mcap);
  ~SlamRunner();
  SlamRunner(const SlamRunner&) = delete;
  SlamRunner& operator=(const SlamRunner&) = delete;

  // Tracks one frame; what the frame became (pose, keypoints' labels, boxes).
  std::shared_ptr<const FrameSnapshot> Process(const RgbdImages& images);
  std::size_t frames() const;
  std::size_t keyframes() const;
  bool semantic() const;
  MapSnapshot SnapshotMap() const;
  std::string DescribeDetector() const;

  // Between frames: the live outputs (app::WriteLiveOutputs: trajectory.txt,
  // keyframes.txt, map_points.ply and frames.csv as they are now; objects.json and
  // cloud_live.ply from the latest snapshot; octomap_live.bt after the semantic
  // thread's current keyframe). The message tells what was done; it starts with
  // "written" on success.
  std::string SaveNow();
  // Finishes the system (its last bundle adjustment) and writes every output and
  // stats.json, with `ended` and `failure` (the error that stopped tracking, or
  // empty). False when an output could not be written (logged).
  bool Finish(const std::string& ended, const std::string& failure, const LiveStats& live);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace sgslam::ros_bridge
