// The files `sgslam run` writes at the end (architecture.md's output contract),
// each from the frame reports or the finished system.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

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

// stats.json sections.
nlohmann::json MedianMsJson(const std::vector<FrameReport>& reports, double median_frame_ms);
nlohmann::json DynamicJson(const std::vector<FrameReport>& reports, const SlamSystem& system);
nlohmann::json LocalMappingJson(const SlamSystem& system);
// Place recognition: relocalisations (lost -> tracked), loops checked, rejected, closed.
nlohmann::json LoopJson(const std::vector<FrameReport>& reports, const SlamSystem& system);
double MedianFrameMs(const std::vector<FrameReport>& reports);

}  // namespace sgslam::app
