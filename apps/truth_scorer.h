// Scores a run against the ground-truth dynamic masks of its sequence, when it
// has them (sgslam synth, dyn_dev): an observer of the run's frame reports and of
// the finished semantic map, outside the SLAM system.
#pragma once

#include <filesystem>
#include <unordered_map>

#include <nlohmann/json.hpp>

#include "sgslam/eval/mask_score.h"
#include "sgslam/io/tum_dataset.h"
#include "sgslam/semantic/semantic_mapper.h"
#include "sgslam/system/slam_system.h"

namespace sgslam::app {

class TruthScorer {
 public:
  explicit TruthScorer(const std::filesystem::path& dataset_dir) : masks_(dataset_dir) {}
  bool active() const { return !masks_.empty(); }

  // The frame's keypoints against its mask (report.keypoints / rejected).
  void AddFrame(const FrameReport& report);
  // stats.json's dynamic.truth; null when no frame had a mask.
  nlohmann::json RejectionJson() const;
  // stats.json's semantic.truth, from the finished map; the keyframes' depth is
  // read again from the dataset (the semantic thread keeps none). Null when inactive.
  nlohmann::json SemanticJson(const SemanticMapper& map, const TumDataset& dataset, const CameraConfig& camera) const;

 private:
  eval::MaskIndex masks_;
  eval::MaskScore rejection_;
};

}  // namespace sgslam::app
