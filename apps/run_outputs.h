// The files of a run's output folder (docs/architecture.md, "Outputs"), each from
// the frame reports or the system: the one writer of each, for `sgslam run` and
// the ROS node alike, so that a name always means the same content.
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
// config_used.yaml: the effective configuration and where it came from (`source`).
void WriteConfigUsed(const std::filesystem::path& out, const Config& config, const std::string& source);
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

// The live outputs, during a run on request (the node's save service; `sgslam run`
// on SIGUSR1 asks for the OctoMap alone): frames.csv, trajectory.txt, keyframes.txt
// and map_points.ply as they are now (what the end writes, earlier); with the
// semantic thread, objects.json from the latest map snapshot (snapshots enabled),
// cloud_live.ply (the snapshot's keyframe clouds at their poses now) and
// octomap_live.bt (requested: RequestLiveOctoMap). The live cloud and OctoMap have
// names of their own: the export filters (seen through, seen moving, seen once, free
// space), the voxel merge and the OctoMap's rebuild from what passed need the
// finished run (SemanticMapper::ExportCloud: after Finish(), once), so they are not
// what cloud.ply and octomap.bt hold.
void WriteLiveOutputs(const std::filesystem::path& out, SlamSystem& system, const std::vector<FrameReport>& reports,
                      FailedOutputs& failed);
// octomap_live.bt: the OctoMap so far, written by the semantic thread after the
// keyframe it is on (at once in sequential mode); never throws.
void RequestLiveOctoMap(const std::filesystem::path& out, SemanticMapper& semantic);

// The files a run writes in its output folder, by name: the contract of the folder
// (what a full run writes at the end).
const std::vector<std::string>& RunOutputNames();
// The files written only on request during a run (WriteLiveOutputs' own names).
const std::vector<std::string>& LiveOutputNames();
// Into plan: the output folder (`role` names it: "--out") and its files (both lists
// above), and the files and folders the configured system reads (the detector's
// model, detections file and the vocabulary); `detections_dir` is where
// detector.backend file looks for detections.txt. `sgslam run` and the ROS node
// check their paths with it.
void PlanRunOutputs(OutputPlan& plan, const Config& config, const std::filesystem::path& out, const std::string& role,
                    const std::filesystem::path& detections_dir);

// stats.json. The counts of a finished run.
struct RunTotals {
  std::size_t frames = 0, tracked = 0, odometry = 0, lost = 0, keyframes = 0, map_points = 0;
  double median_frame_ms = 0, peak_rss_mib = 0;
};
RunTotals TotalsOf(const std::vector<FrameReport>& reports, const SlamSystem& system, std::size_t map_points);
// The sections every run's stats.json has: mode, frames, tracked, lost, keyframes,
// map_points, median_ms, peak_rss_mib, dynamic (rejection, the detector), local_mapping,
// loop (relocalisations, loops checked, rejected and closed, global BAs) and, when
// the final bundle adjustment ran, final_ba (logged). Each caller adds its own.
nlohmann::json SystemStatsJson(const Config& config, const RunTotals& totals, const std::vector<FrameReport>& reports,
                               const SlamSystem& system);
// stats.json's "live" section: frames dropped and the latency from a frame's arrival
// to its pose (median, p95, max), for `run --realtime` and the ROS node.
nlohmann::json LiveJson(std::size_t dropped, const std::vector<double>& latency_ms);
// stats.json, the last output: `stats` with the semantic section (when not null),
// how the run ended (`ended`, or with a failure "failed: <failure>" and "error") and
// failed_outputs, the outputs that failed before it; written through failed too.
void WriteStatsJson(const std::filesystem::path& out, nlohmann::json stats, const nlohmann::json& semantic,
                    const std::string& ended, const std::string& failure, FailedOutputs& failed);

}  // namespace sgslam::app
