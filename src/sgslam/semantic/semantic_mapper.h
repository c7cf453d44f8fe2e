// The semantic mapping thread (paper Fig. 1, Sec. III-E): fed with keyframes once
// local mapping has refined them (pose, colour and depth images, detections, the
// per-keypoint static/dynamic labels of tracking), it builds
//  - a static dense cloud: each keyframe's depth back-projected without its dynamic
//    pixels (dynamic_mask.h), voxel-downsampled and kept in the keyframe's frame, so
//    that export composes it with the keyframe's final pose;
//  - the OctoMap (octomap_builder.h), updated incrementally per keyframe;
//  - the database of 3-D semantic objects (objects.h).
//
// Threading: Submit() is called by one producer (local mapping, or the only thread
// in sequential mode) and never blocks: when queue_size keyframes wait, the oldest
// is dropped and counted. AddFrame() is called by tracking for every frame and
// never blocks either; with box_window > 0 a keyframe waits (in the worker, or
// in sequential mode in a pending list) until the box_window frames after it are
// in, or Finish(). The worker takes Map::mutex() shared only to read poses,
// never while holding its own mutex. Finish() drains the queue and joins; the
// export functions are called after Finish(), under the caller's shared map lock.
// The keyframe queue is a drop-oldest queue like common/bounded_queue.h's, but
// kept under the mapper's own mutex: its front waits for the frames after it (the
// box window), and a pending OctoMap request is served first.
#pragma once

#include <atomic>
#include <condition_variable>
#include <deque>
#include <filesystem>
#include <functional>
#include <memory>
#include <utility>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include <opencv2/core.hpp>

#include "sgslam/common/time.h"
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

struct SemanticStats {
  std::size_t keyframes = 0, dropped = 0;
  std::vector<double> ms;  // per processed keyframe: keyframe detector + mask + cloud + OctoMap + objects
  double median_detect_ms = 0;  // the keyframe detector (semantic.keyframe_model), when there is one
  double median_mask_ms = 0, median_cloud_ms = 0, median_octomap_ms = 0, median_objects_ms = 0;
  std::size_t cloud_points = 0, cloud_points_freed = 0;  // exported, and removed by the free-space filter
};

class SemanticMapper {
 public:
  // keyframe_detector (optional): run on every keyframe's colour image; its
  // dynamic-class boxes join the keyframe's in the dynamic mask
  // (semantic.keyframe_model). Used by the semantic thread alone.
  // camera: the keyframes' camera; classes: which detections are movers.
  SemanticMapper(const SemanticConfig& config, std::shared_ptr<const Camera> camera, ClassTable classes,
                 const Map& map, bool sequential, std::unique_ptr<Detector> keyframe_detector = nullptr);
  ~SemanticMapper();
  SemanticMapper(const SemanticMapper&) = delete;
  SemanticMapper& operator=(const SemanticMapper&) = delete;

  void Submit(SemanticInput input);
  // A frame's pose and detections (only its dynamic-class boxes are kept; a lost
  // frame comes without detections).
  void AddFrame(std::uint64_t frame_id, const SE3& T_c_w, const std::vector<Detection>& detections,
                const cv::Mat& depth_raw);
  void Finish();
  // Writes the live OctoMap (as built so far, before the export filters) to path,
  // atomically: at once in sequential mode, else by the semantic thread after the
  // keyframe it is on. Never throws; a failed write is logged. (sgslam run: SIGUSR1.)
  void RequestOctoMap(const std::filesystem::path& path);
  std::size_t octomaps_written() const;
  bool has_keyframe_detector() const { return has_keyframe_detector_; }

  // Calls fn with a copy of the semantic map's state (keyframes shared): at once in
  // sequential mode or after Finish(), else on the semantic thread after the
  // keyframe it is on, so fn must hand it over rather than work on it there (the
  // thread runs at the lowest priority: a lock held on it may be held long).
  void RequestState(std::function<void(SemanticState)> fn);
  // Starts from a saved state (before the first Submit; the keyframes are in the
  // map): the clouds, the objects, and the OctoMap built again with the keyframes'
  // poses now (by the worker, before its first keyframe; at once when sequential).
  void Restore(SemanticState state);

  // For observers (system/snapshot.h): once enabled (before the first Submit), each
  // keyframe's cloud, the objects estimated after it and the OctoMap's occupied
  // cells are published; Published()
  // copies them (shared pointers) from any thread.
  void EnablePublishing() { publishing_ = true; }
  struct Published {
    std::vector<std::pair<std::shared_ptr<KeyFrame>, std::shared_ptr<const std::vector<ColoredPoint>>>> clouds;
    std::vector<ObjectEstimate> objects;  // world frame
    // The OctoMap's occupied cells after the last keyframe: centre (m, world), side.
    std::shared_ptr<const std::vector<Eigen::Vector4f>> cells;
  };
  Published published() const;

  // After Finish(), under the map's shared lock.
  void ExportCloud(std::vector<Eigen::Vector3d>& points, std::vector<Rgb>& colours);
  std::size_t inconsistent_points() const { return inconsistent_; }
  std::size_t unsupported_points() const { return unsupported_; }
  std::size_t seen_moving_points() const { return seen_moving_; }
  // T_out_w: the frame to express the objects in (boxes are axis-aligned in it).
  std::vector<ObjectEstimate> ExportObjects(const SE3& T_out_w = SE3()) const;
  OctoMapBuilder& octomap() { return octomap_; }
  const OctoMapBuilder& octomap() const { return octomap_; }
  SemanticStats stats() const;

  // After Finish(), for evaluation (eval/semantic_score.h): each mapped keyframe
  // with its static points in its camera frame (before the export's free-space
  // rule), whether a world point survives that rule, and what the map was made with.
  struct KeyFramePoints {
    std::shared_ptr<KeyFrame> keyframe;
    const std::vector<ColoredPoint>* points_c;
  };
  std::vector<KeyFramePoints> KeyFrameClouds() const;
  bool Exported(const Eigen::Vector3d& p_w) const;
  const SemanticConfig& config() const { return config_; }
  const Camera& camera() const { return *camera_; }

 private:
  void Loop();
  void ProcessKeyFrame(const SemanticInput& input, const std::vector<CarriedBox>& carried);
  // ProcessKeyFrame's steps: the keyframe's movers (its boxes and the keyframe
  // detector's); its dynamic pixel mask (surface: the movers' own pixels, for the
  // seen-moving filter; null when that is off); its static cloud; its objects.
  std::vector<Detection> Movers(const SemanticInput& input);
  cv::Mat DynamicMask(const SemanticInput& input, const std::vector<Detection>& movers,
                      const std::vector<CarriedBox>& carried, cv::Mat* surface) const;
  struct KeyFrameCloud;
  KeyFrameCloud MakeCloud(const SemanticInput& input, const cv::Mat& mask, const cv::Mat& surface) const;
  void ObserveObjects(const SemanticInput& input, const SE3& T_w_c);
  // Under mutex_: the boxes of the frames around the keyframe's, in its image.
  std::vector<CarriedBox> CarriedBoxes(std::uint64_t keyframe_frame_id) const;
  bool WindowComplete(std::uint64_t keyframe_frame_id) const;  // under mutex_
  void ProcessReady(bool all);                                 // sequential mode

  const SemanticConfig config_;
  const Map& map_;
  const bool sequential_;
  std::shared_ptr<const Camera> camera_;
  PixelRays rays_;
  ClassTable classes_;
  std::unique_ptr<Detector> keyframe_detector_;  // the worker's alone (reset if it fails)
  const bool has_keyframe_detector_;

  struct KeyFrameCloud {
    std::shared_ptr<KeyFrame> keyframe;
    std::vector<ColoredPoint> points_c;
    cv::Mat depth_pooled;  // m (CV_32F), min over pool^2 pixels of valid depth; 0 = none
    cv::Mat moving_pooled;  // the same over the pixels the keyframe's dynamic mask marks
  };
  // Drops the points other keyframes see through (consistency_filter) and those
  // fewer than min_view_support keyframes saw (DropPointsSeenOnce), and rebuilds
  // the OctoMap from the rest with the current poses; once, on first export.
  void FilterAndRebuild();
  bool filtered_ = false;
  std::size_t inconsistent_ = 0;
  std::size_t unsupported_ = 0;
  std::size_t seen_moving_ = 0;
  // One pass over the other keyframes' pooled depths: drops the points that at least
  // consistency_min_votes of them see through (consistency_filter), then those they
  // masked as a mover often enough (seen_moving_ratio).
  void DropPointsOtherViewsContradict(const std::vector<SE3>& T_c_w, const std::vector<SE3>& T_w_c);
  // Drops the points whose voxel neighbourhood fewer than min_view_support keyframes saw.
  void DropPointsSeenOnce(const std::vector<SE3>& T_w_c);
  std::vector<std::vector<ColoredPoint>> ray_points_;  // per cloud: the free-space ray ends, for the rebuild
  // Owned by the worker until Finish() (then by the exporting caller).
  std::vector<KeyFrameCloud> clouds_;
  OctoMapBuilder octomap_;
  ObjectDatabase objects_;

  std::atomic<bool> publishing_{false};
  void Publish(const KeyFrameCloud& cloud);  // the worker (or the only thread)
  mutable std::mutex published_mutex_;       // guards published_; never held with mutex_ or the map's
  Published published_;

  mutable std::mutex mutex_;  // guards queue_, frames_, last_frame_id_, stats_, stop_, octomap_request_
  std::condition_variable wake_;
  std::deque<SemanticInput> queue_;  // parallel: waiting for the worker; sequential: for their box window
  std::deque<FrameBoxes> frames_;    // the last frames (a bounded history), by frame id
  std::optional<std::uint64_t> last_frame_id_;
  std::optional<std::filesystem::path> octomap_request_;  // guarded by mutex_
  std::function<void(SemanticState)> state_request_;  // guarded by mutex_
  bool rebuild_pending_ = false;                              // guarded by mutex_ (Restore)
  void RebuildOctoMap();  // from clouds_ with the keyframes' poses now; the worker (or the only thread)
  SemanticState State() const;  // the worker (or the only thread)
  std::size_t octomaps_written_ = 0;                      // guarded by mutex_
  void WriteLiveOctoMap(const std::filesystem::path& path);  // the worker (or the only thread)
  mutable SemanticStats stats_;
  struct StageMs {
    double detect, mask, cloud, octomap, objects;
  };
  std::vector<StageMs> stage_ms_;  // guarded by mutex_
  bool stop_ = false;
  bool finished_ = false;
  std::thread thread_;
};

}  // namespace sgslam
