// The body of `sgslam run`, shared with `sgslam demo`: configure, stream the
// dataset through the SLAM system and write every output of the contract.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "sgslam/config/config.h"

namespace sgslam::app {

inline constexpr int kDefaultViewerPort = 7117;

struct RunOptions {
  std::string dataset, config, out, model;
  std::string mode;  // empty: the config's dynamic.mode (default sg)
  bool no_detector = false, sequential = false;
  // Hand frames over at the pace of their timestamps, as a live camera would
  // (ORB-SLAM2's TUM example does the same); otherwise as fast as they load. A
  // frame that arrives while the system is busy waits in a one-slot buffer, where
  // a newer frame replaces it (dropped, counted), unless every_frame.
  bool realtime = false;
  bool every_frame = false;
  std::size_t max_frames = 0;
  // Map reuse: the map to start from (relocalised in at the first frame), and the
  // file to save the map to at the end and on SIGUSR1.
  std::string load_map, save_map;
  bool localize = false;  // with load_map: track in the map without adding to it
  // --viewer[=PORT]: the live web viewer (viewer/) on viewer_address; -1: none.
  int viewer_port = -1;
  std::string viewer_address = "127.0.0.1";
  std::vector<std::string> viewer_origins;  // --viewer-origin: pages elsewhere allowed (a name, a proxy)
  // --foxglove[=PORT]: Foxglove's WebSocket protocol (run_foxglove.h) on foxglove_address; -1: none.
  int foxglove_port = -1;
  std::string foxglove_address = "127.0.0.1";
  std::string mcap;  // --mcap FILE: the run recorded for Foxglove (mcap_recorder.h); empty: none
  bool print_objects = true;  // the end-of-run object table on stdout
  // --object-truth FILE: the sequence's true objects, to score the object map
  // against (eval/object_score.h); empty: the dataset's objects_gt.json, if any.
  std::string object_truth;
  // Programmatic overrides after the file and the options above (the demo's
  // comparison runs); `tweak_name` is added to the configuration's source.
  std::function<void(Config&)> tweak;
  std::string tweak_name;
};

struct RunSummary {
  std::filesystem::path out;
  std::size_t frames = 0, tracked = 0, odometry = 0, lost = 0, keyframes = 0, map_points = 0;
  double median_frame_ms = 0, fps = 0, peak_rss_mib = 0;
  std::optional<double> ate_rmse;  // when the dataset has groundtruth.txt
  std::size_t ate_pairs = 0;
  int stopped_by = 0;  // the signal that stopped the run early (SIGINT, SIGTERM, SIGHUP), else 0
};

// Throws sgslam::Error for bad input; outputs of the frames processed before a
// failure, or a stop signal, are written before the error is passed on.
RunSummary RunSequence(const RunOptions& options);

// The one-line summary printed at the end of a run.
std::string FormatSummary(const RunSummary& s);

}  // namespace sgslam::app
