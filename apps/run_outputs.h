// The files `sgslam run` writes at the end (docs/architecture.md, "Outputs"),
// each from the frame reports or the finished system.
#pragma once

#include <exception>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

#include <nlohmann/json.hpp>

#include "sgslam/config/config.h"
#include "sgslam/io/output_plan.h"
#include "sgslam/io/trajectory.h"
#include "sgslam/system/slam_system.h"

namespace sgslam::app {

// frames.csv: one row a frame.
void WriteFramesCsv(const std::filesystem::path& path, const std::vector<FrameReport>& reports);
// detections.txt in the file backend's format (detection/detections_file.h), so a
// later run can replay them; takes the reports' boxes.
void WriteDetections(const std::filesystem::path& path, std::vector<FrameReport>& reports);
// Runs one output's writer, by name, keeping a failure from the others.
using OutputWriter = std::function<void(const std::string& name, const std::function<void()>& write)>;
// cloud.ply, octomap.bt, objects.json, map_top.png, each through write_output so
// that one that cannot be written keeps none of the others back (and the object
// table on stdout when print_objects); returns stats.json's semantic section.
nlohmann::json WriteSemanticMap(const std::filesystem::path& out, SlamSystem& system, const Trajectory& trajectory,
                                bool print_objects, const OutputWriter& write_output);

// Runs each output's writer and keeps the names of those that failed (logged).
struct FailedOutputs {
  std::vector<std::string> names;
  template <typename Fn>
  void Try(const std::string& name, Fn write) {
    try {
      write();
    } catch (const std::exception& e) {
      spdlog::error("{} not written: {}", name, e.what());
      names.push_back(name);
    }
  }
  std::string Joined() const;
};

struct RunMaps {
  Trajectory trajectory;
  std::size_t map_points = 0;
  nlohmann::json semantic;  // stats.json's semantic section; null without the semantic thread
};

// Every output of a finished system but stats.json, each on its own: frames.csv,
// detections.txt (has_detector), the trajectories, map_points.ply and the semantic
// map. `sgslam run` and the ROS node write the same files.
RunMaps WriteSystemOutputs(const std::filesystem::path& out, SlamSystem& system, std::vector<FrameReport>& reports,
                           bool has_detector, bool print_objects, FailedOutputs& failed);

// The files a run writes in its output folder, by name: the contract of the folder.
const std::vector<std::string>& RunOutputNames();
// Into plan: the output folder (`role` names it: "--out") and its files, and the
// files and folders the configured system reads (the detector's model, detections
// file and the vocabulary); `detections_dir` is where detector.backend file looks
// for detections.txt. `sgslam run` and the ROS node check their paths with it.
void PlanRunOutputs(OutputPlan& plan, const Config& config, const std::filesystem::path& out, const std::string& role,
                    const std::filesystem::path& detections_dir);

// stats.json sections.
nlohmann::json MedianMsJson(const std::vector<FrameReport>& reports, double median_frame_ms);
nlohmann::json DynamicJson(const std::vector<FrameReport>& reports, const SlamSystem& system);
nlohmann::json LocalMappingJson(const SlamSystem& system);
// Place recognition: relocalisations (lost -> tracked), loops checked, rejected, closed.
nlohmann::json LoopJson(const std::vector<FrameReport>& reports, const SlamSystem& system);
double MedianFrameMs(const std::vector<FrameReport>& reports);
// stats.json's "live" section: frames dropped and the latency from a frame's arrival
// to its pose (median, p95, max), for `run --realtime` and the ROS node.
nlohmann::json LiveJson(std::size_t dropped, const std::vector<double>& latency_ms);

}  // namespace sgslam::app
