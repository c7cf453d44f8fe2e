// Keyframes for the export-filter tests: depth images added to a SemanticMap (no
// thread) as keyframes whose camera steps sideways by 5 mm each (a patch
// stays within one voxel), then the exported cloud in keyframe 0's frame.
#pragma once

#include <memory>
#include <opencv2/core.hpp>
#include <shared_mutex>
#include <vector>

#include "sgslam/map/features.h"
#include "sgslam/map/keyframe.h"
#include "sgslam/map/map.h"
#include "sgslam/semantic/semantic_map.h"

namespace sgslam::test {

struct SteppedCloud {
  std::vector<Eigen::Vector3d> points;
  std::size_t seen_moving = 0, unsupported = 0;  // the map's counters of dropped points
};

// depths[k]: keyframe k's raw depth (5000 per metre); boxes[k], if given, its detections;
// keyframe_detector, if given, the semantic thread's own (semantic.keyframe_model);
// options: the export filters' parameters (default: the pipeline's constants);
// model_level: the keyframe detector's view gate level (SemanticMap::SetModelLevel).
inline SteppedCloud ExportSteppedKeyframes(const Config& config, const std::vector<cv::Mat>& depths,
                                           const std::vector<std::vector<Detection>>& boxes = {},
                                           std::unique_ptr<Detector> keyframe_detector = nullptr,
                                           const SemanticMapOptions& options = {}, int model_level = 0) {
  Map map;
  SemanticMap semantic(config.semantic, std::make_shared<Camera>(config.camera), ClassTable(config.detector), map,
                       std::move(keyframe_detector), options);
  semantic.SetModelLevel(model_level);
  const auto camera = std::make_shared<Camera>(config.camera);
  const auto scale = std::make_shared<ScaleLevels>(features::MakeScaleLevels(1.2, 8));
  const cv::Mat bgr(depths.at(0).size(), CV_8UC3, cv::Scalar(90, 120, 150));
  for (std::size_t k = 0; k < depths.size(); ++k) {
    auto f = MakeFeatures({}, cv::Mat(0, 32, CV_8U), depths[k], camera, scale, {},
                          k < boxes.size() ? boxes[k] : std::vector<Detection>());
    const SE3 T_c_w(Eigen::Quaterniond::Identity(), Eigen::Vector3d(-0.005 * static_cast<double>(k), 0, 0));
    auto kf = std::make_shared<KeyFrame>(map.NewKeyFrameId(), static_cast<std::uint64_t>(k), 0, f, T_c_w);
    map.AddKeyFrame(kf);
    semantic.Add({kf, bgr, depths[k]}, {});
  }
  SteppedCloud out;
  std::vector<Rgb> colours;
  {
    std::shared_lock lock(map.mutex());
    semantic.ExportCloud(out.points, colours);
  }
  out.seen_moving = semantic.seen_moving_points();
  out.unsupported = semantic.unsupported_points();
  return out;
}

}  // namespace sgslam::test
