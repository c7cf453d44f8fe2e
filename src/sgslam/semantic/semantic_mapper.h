// The semantic mapping thread (paper Fig. 1, Sec. III-E): runs the semantic map
// (semantic_map.h: static cloud, OctoMap, objects) on the keyframes local mapping
// has refined, each masked with the boxes of the frames around it (the box window),
// and serves requests for its state while it runs.
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
// box window), and a pending request is served first.
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
#include "sgslam/semantic/semantic_config.h"
#include "sgslam/semantic/semantic_map.h"

namespace sgslam {

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
  bool has_keyframe_detector() const { return map_.has_keyframe_detector(); }

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

  // After Finish(), under the map's shared lock (semantic_map.h).
  void ExportCloud(std::vector<Eigen::Vector3d>& points, std::vector<Rgb>& colours);
  std::size_t inconsistent_points() const { return map_.inconsistent_points(); }
  std::size_t unsupported_points() const { return map_.unsupported_points(); }
  std::size_t seen_moving_points() const { return map_.seen_moving_points(); }
  std::vector<ObjectEstimate> ExportObjects(const SE3& T_out_w = SE3()) const { return map_.ExportObjects(T_out_w); }
  OctoMapBuilder& octomap() { return map_.octomap(); }
  const OctoMapBuilder& octomap() const { return map_.octomap(); }
  SemanticStats stats() const;
  // After Finish(), for evaluation (eval/semantic_score.h).
  using KeyFramePoints = SemanticMap::KeyFramePoints;
  std::vector<KeyFramePoints> KeyFrameClouds() const { return map_.KeyFrameClouds(); }
  bool Exported(const Eigen::Vector3d& p_w) const { return map_.Exported(p_w); }
  const SemanticConfig& config() const { return config_; }
  const Camera& camera() const { return map_.camera(); }

 private:
  void Loop();
  // The map's Add, then publishing and the stats.
  void ProcessKeyFrame(const SemanticInput& input, const std::vector<CarriedBox>& carried);
  // Under mutex_: the boxes of the frames around the keyframe's, in its image.
  std::vector<CarriedBox> CarriedBoxes(std::uint64_t keyframe_frame_id) const;
  bool WindowComplete(std::uint64_t keyframe_frame_id) const;  // under mutex_
  void ProcessReady(bool all);                                 // sequential mode
  void WriteLiveOctoMap(const std::filesystem::path& path);     // the worker (or the only thread)

  const SemanticConfig config_;
  const bool sequential_;
  std::shared_ptr<const Camera> camera_;
  ClassTable classes_;
  // The worker's until Finish() (then the exporting caller's); sequential: the only thread's.
  SemanticMap map_;

  std::atomic<bool> publishing_{false};
  mutable std::mutex published_mutex_;  // guards published_; never held with mutex_ or the map's
  Published published_;

  mutable std::mutex mutex_;  // guards queue_, frames_, last_frame_id_, stats_, stop_ and the requests
  std::condition_variable wake_;
  std::deque<SemanticInput> queue_;  // parallel: waiting for the worker; sequential: for their box window
  std::deque<FrameBoxes> frames_;    // the last frames (a bounded history), by frame id
  std::optional<std::uint64_t> last_frame_id_;
  std::optional<std::filesystem::path> octomap_request_;
  std::function<void(SemanticState)> state_request_;
  bool rebuild_pending_ = false;  // Restore
  std::size_t octomaps_written_ = 0;
  mutable SemanticStats stats_;
  std::vector<SemanticMap::StageMs> stage_ms_;
  bool stop_ = false;
  bool finished_ = false;
  std::thread thread_;
};

}  // namespace sgslam
