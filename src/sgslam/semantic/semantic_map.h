// The semantic map (paper Sec. III-E), built one keyframe at a time from its pose,
// colour and depth images, detections and the per-keypoint static/dynamic labels
// of tracking:
//  - a static dense cloud: each keyframe's depth back-projected without its dynamic
//    pixels (dynamic_mask.h), voxel-downsampled and kept in the keyframe's frame, so
//    that export composes it with the keyframe's final pose;
//  - the OctoMap (octomap_builder.h), updated incrementally per keyframe;
//  - the database of 3-D semantic objects (objects.h).
// The masks leave the image border (kImageBorder) and the movers out; the export
// filters (semantic.filters: see_through, seen_moving, view_support, free_space) run
// once, on the first export.
//
// Single-threaded: one thread at a time (semantic_mapper.h runs it on the semantic
// thread, or inline in sequential mode). It reads keyframe poses under the Map's
// shared lock, never holding another.
#pragma once

#include <atomic>
#include <filesystem>
#include <optional>
#include <memory>
#include <unordered_map>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "sgslam/detection/detector.h"
#include "sgslam/detection/detector_config.h"
#include "sgslam/semantic/box_window.h"
#include "sgslam/semantic/cloud.h"
#include "sgslam/semantic/objects.h"
#include "sgslam/semantic/octomap_builder.h"
#include "sgslam/semantic/semantic_config.h"

namespace sgslam {

class Camera;
class KeyFrame;
class Map;

// px; with semantic.filters.image_border, the strip this wide at the image border
// is masked: ORB finds no keypoints there (no motion evidence) and the detector
// misses the people it cuts; static surfaces there are seen from other keyframes
// (dyn_dev: cloud on movers 0.40 % -> 0.14 %, 0.18 % at 24 px; OctoMap path cells
// 39 -> 9; docs/results-archive.md, "Border strip and seen-moving filter").
inline constexpr int kImageBorder = 32;
// With semantic.filters.seen_moving, a point is dropped when other keyframes masked
// a mover at its place at least once and at least this many times as often as
// keyframes saw it there unmasked (its own counts): with the 32 px border, 0.14 % ->
// 0.08 % of the cloud on movers on dyn_dev.
inline constexpr double kSeenMovingRatio = 3.0;

// With semantic.filters.view_support, a point stays only when this many keyframes
// put points within one OctoMap voxel of it (or the 26 around): a mover crosses a
// place in a keyframe or two, a static surface is seen again (dyn_dev: cloud on
// movers 0.91 % -> 0.53 %, OctoMap path cells 6.0 % -> 0.73 %; 2: 0.65 % / 2.0 %;
// 4: 0.46 % / 0.48 % with 10 % fewer points on the static fr1_rpy).
inline constexpr int kMinViewSupport = 3;
// The keyframe detector's view gate (SemanticMap::SetModelLevel): it runs again
// once the view turned this much or moved this far from its last keyframe.
inline constexpr double kModelViewDeg = 5.0;
inline constexpr double kModelViewMetres = 0.10;

// The export filters' and the keyframe model's parameters that the tests vary;
// the pipeline passes the constants.
struct SemanticMapOptions {
  double seen_moving_ratio = kSeenMovingRatio;  // see kSeenMovingRatio
  double model_view_deg = kModelViewDeg;        // see kModelViewDeg (0 and 0: every keyframe)
  double model_view_metres = kModelViewMetres;
};

struct SemanticInput {
  std::shared_ptr<KeyFrame> keyframe;
  cv::Mat bgr;    // the keyframe's colour image (shared, never written)
  cv::Mat depth;  // raw 16-bit depth
};

// What the semantic map is made of, to save a map and load it again (mapfile/):
// each keyframe's static cloud with the data the export's filters and the OctoMap
// need, and the object database. The OctoMap is rebuilt from the clouds.
struct SemanticState {
  struct Cloud {
    std::shared_ptr<KeyFrame> keyframe;
    std::vector<ColoredPoint> points_c;  // static points, camera frame
    std::vector<ColoredPoint> rays_c;    // the free-space ray ends (kOctoMapRayStride)
    cv::Mat depth_pooled, moving_pooled;  // CV_32F (see KeyFrameCloud); may be empty
  };
  std::vector<Cloud> clouds;
  std::vector<ObjectDatabase::Object> objects;
  int next_object_id = 1;
};

class SemanticMap {
 public:
  // keyframe_detector (optional): run on the colour image of each keyframe with a
  // new view (NewView); its dynamic-class boxes join the keyframe's in the dynamic
  // mask, its others give the objects (semantic.keyframe_model). camera: the keyframes'; classes: which detections
  // are movers; map: the keyframes' poses.
  SemanticMap(const SemanticConfig& config, std::shared_ptr<const Camera> camera, ClassTable classes,
              const Map& map, std::unique_ptr<Detector> keyframe_detector = nullptr,
              const SemanticMapOptions& options = {});

  struct StageMs {  // what Add spent on each step
    double detect = 0, mask = 0, cloud = 0, octomap = 0, objects = 0;
    bool model_ran = false;  // the keyframe detector ran on this keyframe
  };
  // One keyframe: its movers (its boxes and the keyframe detector's), its dynamic
  // pixel mask (with `carried`, the box window's boxes), its static cloud, the
  // OctoMap, its objects.
  StageMs Add(const SemanticInput& input, const std::vector<CarriedBox>& carried);
  std::size_t keyframes() const { return clouds_.size(); }
  bool has_keyframe_detector() const { return has_keyframe_detector_; }
  // The keyframe detector runs on a keyframe whose view turned at least
  // kModelViewDeg or moved kModelViewMetres, times 2^level, from the last keyframe
  // it ran on (the CPU budget raises the level: system/cpu_budget.h). Any thread.
  void SetModelLevel(int level) { model_level_.store(level); }

  // Map reuse: a copy of the state (keyframes shared); Restore starts from one
  // (before the first Add; the keyframes are in the map), then RebuildOctoMap
  // builds the OctoMap again with the keyframes' poses now.
  SemanticState State() const;
  void Restore(SemanticState state);
  void RebuildOctoMap();

  // The live OctoMap (before the export filters), written atomically; throws.
  void WriteOctoMap(const std::filesystem::path& path);

  // For observers: the last keyframe's cloud, the objects estimated now (world)
  // and the OctoMap's occupied cells (centre, side).
  struct Snapshot {
    std::shared_ptr<KeyFrame> keyframe;
    std::shared_ptr<const std::vector<ColoredPoint>> cloud;
    std::vector<ObjectEstimate> objects;
    std::shared_ptr<const std::vector<Eigen::Vector4f>> cells;
  };
  Snapshot Latest() const;  // after an Add

  // Export, under the map's shared lock: the filters run on the first call.
  // Returns the points the free-space rule removed.
  std::size_t ExportCloud(std::vector<Eigen::Vector3d>& points, std::vector<Rgb>& colours);
  std::size_t inconsistent_points() const { return inconsistent_; }
  std::size_t unsupported_points() const { return unsupported_; }
  std::size_t seen_moving_points() const { return seen_moving_; }
  std::size_t objects_removed() const { return objects_removed_; }
  // T_out_w: the frame to express the objects in (boxes are axis-aligned in it).
  std::vector<ObjectEstimate> ExportObjects(const SE3& T_out_w = SE3()) const;
  OctoMapBuilder& octomap() { return octomap_; }
  const OctoMapBuilder& octomap() const { return octomap_; }

  // For evaluation (eval/semantic_score.h): each keyframe with its static points
  // in its camera frame (before the export's free-space rule), and whether a world
  // point survives that rule.
  struct KeyFramePoints {
    std::shared_ptr<KeyFrame> keyframe;
    const std::vector<ColoredPoint>* points_c;
  };
  std::vector<KeyFramePoints> KeyFrameClouds() const;
  bool Exported(const Eigen::Vector3d& p_w) const;
  const SemanticConfig& config() const { return config_; }
  const Camera& camera() const { return *camera_; }

 private:
  struct KeyFrameBoxes {
    std::vector<Detection> movers;   // the keyframe's boxes and the keyframe model's movers
    std::vector<Detection> objects;  // the keyframe model's boxes, else the keyframe's own
    bool model_ran = false;          // the keyframe model gave them (objects: none when it did not run)
  };
  KeyFrameBoxes Detect(const SemanticInput& input, const SE3& T_w_c);
  // The keyframe detector's view gate (SetModelLevel).
  bool NewView(const SE3& T_w_c) const;
  // surface: the movers' own pixels, for the seen-moving filter; null when that is off.
  cv::Mat DynamicMask(const SemanticInput& input, const std::vector<Detection>& movers,
                      const std::vector<CarriedBox>& carried, cv::Mat* surface) const;
  struct KeyFrameCloud {
    std::shared_ptr<KeyFrame> keyframe;
    std::vector<ColoredPoint> points_c;
    cv::Mat depth_pooled;   // m (CV_32F), min over pool^2 pixels of valid depth; 0 = none
    cv::Mat moving_pooled;  // the same over the pixels the keyframe's dynamic mask marks
  };
  KeyFrameCloud MakeCloud(const SemanticInput& input, const cv::Mat& mask, const cv::Mat& surface) const;
  // movers_mask: the keyframe's moving pixels (no image border), left out of the objects.
  void ObserveObjects(const SemanticInput& input, const std::vector<Detection>& detections, const SE3& T_w_c,
                      const cv::Mat& movers_mask);
  static void MaskImageBorder(cv::Mat& mask);
  // T_w_c of every keyframe with a cloud (those of the objects' views too), read
  // under the map's shared lock, to be used outside it.
  std::unordered_map<const KeyFrame*, SE3> KeyFramePoses() const;
  // Drops the points other keyframes see through (filters.see_through) or masked as
  // a mover (filters.seen_moving) and those fewer than kMinViewSupport keyframes saw
  // (filters.view_support), and rebuilds the OctoMap from the rest with the current
  // poses; once, on first export.
  void FilterAndRebuild();
  // One pass over the other keyframes' pooled depths: drops the points that at least
  // kConsistencyMinVotes of them see through (filters.see_through), then those they
  // masked as a mover often enough (filters.seen_moving, options_.seen_moving_ratio).
  void DropPointsOtherViewsContradict(const std::vector<SE3>& T_c_w, const std::vector<SE3>& T_w_c);
  // Drops the points whose voxel neighbourhood fewer than kMinViewSupport keyframes saw.
  void DropPointsSeenOnce(const std::vector<SE3>& T_w_c);

  const SemanticConfig config_;
  const SemanticMapOptions options_;
  const Map& map_;
  std::shared_ptr<const Camera> camera_;
  PixelRays rays_;
  ClassTable classes_;
  std::unique_ptr<Detector> keyframe_detector_;  // reset if it fails
  const bool has_keyframe_detector_;
  std::optional<SE3> model_T_w_c_;  // the last keyframe the keyframe detector ran on (at the time)
  std::atomic<int> model_level_{0};
  std::vector<KeyFrameCloud> clouds_;
  std::vector<std::vector<ColoredPoint>> ray_points_;  // per cloud: the free-space ray ends, for the rebuilds
  OctoMapBuilder octomap_;
  ObjectDatabase objects_;
  bool filtered_ = false;
  std::size_t inconsistent_ = 0, unsupported_ = 0, seen_moving_ = 0;
  std::size_t objects_removed_ = 0;  // seen missing where they were (ObjectDatabase::CountViews)
};

}  // namespace sgslam
