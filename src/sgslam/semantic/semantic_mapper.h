// The semantic mapping thread (paper Fig. 1, Sec. III-E): runs the semantic map
// (semantic_map.h: static cloud, OctoMap, objects) on the keyframes local mapping
// has refined, each masked with the boxes of the frames around it (the box window),
// and serves requests for its state while it runs.
//
// Threading: the map runs on a Stage (common/stage.h): inline on the thread that
// hands it keyframes (--sequential), or on the thread `sg-semantic` behind a
// drop-oldest queue of semantic.queue_size keyframes whose box window is complete
// (the oldest is dropped and counted; the thread at the lowest CPU priority with
// semantic.low_priority).
// Submit() is called by one producer (local mapping) and AddFrame() by tracking for
// every frame; neither blocks. With semantic.filters.box_window a keyframe waits in
// a pending list until the kBoxWindow frames after it (semantic_mapper.cpp) are in,
// or Finish(), and goes to the stage with the boxes carried into it, in order.
// Requests (RequestOctoMap, RequestState, Restore's rebuild) wait in slots that
// the stage serves before its next keyframe, so they need not wait for a queue of
// keyframes. The map takes Map::mutex() shared only to read poses. Finish() hands
// over the pending keyframes, drains the stage and serves what requests are left;
// the export functions are called after Finish(), under the caller's shared map lock.
#pragma once

#include <atomic>
#include <deque>
#include <filesystem>
#include <functional>
#include <memory>
#include <utility>
#include <mutex>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "sgslam/common/stage.h"
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
  double median_detect_ms = 0;  // the keyframe detector (semantic.keyframe_model) where it ran
  std::size_t model_keyframes = 0;  // keyframes it ran on (SemanticMap::NewView)
  double median_mask_ms = 0, median_cloud_ms = 0, median_octomap_ms = 0, median_objects_ms = 0;
  std::size_t cloud_points = 0, cloud_points_freed = 0;  // exported, and removed by the free-space filter
};

class SemanticMapper {
 public:
  // keyframe_detector (optional): run on the colour image of each keyframe with a
  // new view (SemanticMap::NewView); its dynamic-class boxes join the keyframe's in
  // the dynamic mask, its others give the objects (semantic.keyframe_model). Used by the semantic thread alone.
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
  // The keyframe detector's view gate, times 2^level (SemanticMap::SetModelLevel; any thread).
  void SetModelLevel(int level) { map_.SetModelLevel(level); }

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
  std::size_t objects_removed() const { return map_.objects_removed(); }
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
  // What the stage works on: a keyframe with the boxes carried into it, or nothing
  // (a wake-up to serve the requests).
  struct Job {
    std::optional<SemanticInput> keyframe;
    std::vector<CarriedBox> carried;
  };
  void Work(Job job);  // on the stage
  void ServeRequests();  // on the stage (or the only thread after Finish)
  // Posts an empty job unless a job is queued already (which serves the requests
  // first): never pushes a keyframe out of a full queue.
  void Wake();
  // Under window_mutex_: hands the pending keyframes whose window is complete (all:
  // every one) to the stage, in order.
  void Release(bool all);
  // Under window_mutex_: the boxes of the frames around the keyframe's, in its image.
  std::vector<CarriedBox> CarriedBoxes(std::uint64_t keyframe_frame_id) const;
  bool WindowComplete(std::uint64_t keyframe_frame_id) const;  // under window_mutex_
  // The map's Add, then publishing and the stats.
  void ProcessKeyFrame(const SemanticInput& input, const std::vector<CarriedBox>& carried);
  void WriteLiveOctoMap(const std::filesystem::path& path);

  const SemanticConfig config_;
  std::shared_ptr<const Camera> camera_;
  ClassTable classes_;
  // The stage's until Finish() (then the exporting caller's).
  SemanticMap map_;

  std::atomic<bool> publishing_{false};
  mutable std::mutex published_mutex_;  // guards published_; never held with mutex_ or the map's
  Published published_;

  // Guards pending_, frames_ and last_frame_id_, and orders the hand-over; held
  // while an inline stage works (which never takes it).
  std::mutex window_mutex_;
  std::deque<SemanticInput> pending_;  // waiting for their box window
  std::deque<FrameBoxes> frames_;      // the last frames (a bounded history), by frame id
  std::optional<std::uint64_t> last_frame_id_;

  mutable std::mutex mutex_;  // guards the requests, octomaps_written_, stats_ and stage_ms_
  std::optional<std::filesystem::path> octomap_request_;
  std::function<void(SemanticState)> state_request_;
  bool rebuild_pending_ = false;  // Restore
  std::size_t octomaps_written_ = 0;
  mutable SemanticStats stats_;
  std::vector<SemanticMap::StageMs> stage_ms_;
  std::atomic<bool> finished_{false};

  Stage<Job> stage_;  // last: its thread ends before the members it uses go
};

}  // namespace sgslam
