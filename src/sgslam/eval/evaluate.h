// The whole `sgslam eval` computation on two TUM files, and its two renderings
// (a human-readable table and one JSON object), kept out of the command line so
// tests can compare the printed numbers with the library's.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "sgslam/common/time.h"
#include "sgslam/eval/ate.h"
#include "sgslam/eval/rpe.h"
#include "sgslam/io/trajectory.h"

namespace sgslam::eval {

struct EvalOptions {
  Timestamp max_difference = 20'000'000;  // ns (0.02 s), association window for ATE
  Timestamp rpe_delta = kNsPerSecond;     // ns (1 s), RPE pose-pair spacing
  // The ATE alignment is fitted on this trajectory (in the same frame as the
  // estimate: the run that made a map the estimate was localised in), not on the estimate.
  std::filesystem::path align_with;
};

struct EvalReport {
  std::string gt_name, est_name;  // the paths as given
  Trajectory gt, est;             // as read, sorted, one pose per stamp
  EvalOptions options;
  AteResult ate;
  std::optional<RpeResult> rpe;  // absent when the estimate is too short for RPE
  std::string rpe_note;          // why rpe is absent
};

// Keeps the last pose of each timestamp, as the scripts' dict-based readers do.
Trajectory UniqueStamps(const Trajectory& sorted);

// Reads both files and computes ATE and, when possible, RPE. Throws InputError /
// ParseError naming the file for missing, malformed or non-overlapping input.
EvalReport EvaluateFiles(const std::filesystem::path& gt, const std::filesystem::path& est,
                         const EvalOptions& options = {});

nlohmann::json ToJson(const ErrorStats& stats);
nlohmann::json ToJson(const EvalReport& report);
std::string FormatTable(const EvalReport& report);

}  // namespace sgslam::eval
