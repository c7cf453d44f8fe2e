// The SLAM system facade: owns the map, the tracker, local mapping and loop
// closing with their threads, and turns RGB-D images into poses. In sequential
// mode every module is stepped in the caller's thread, so output is identical on
// every run; otherwise local mapping runs on its own thread fed by a bounded
// keyframe queue, and hands each keyframe it finished to the loop thread. A loop
// correction pauses local mapping by taking the mutex local mapping holds while
// it works on a keyframe (mapping_step_mutex_, taken before the map's lock).
//
// Threading: Process() and the result accessors are called from one thread; the
// snapshot accessors (LatestFrame, SnapshotMap) from any thread.
#pragma once

#include <atomic>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "sgslam/common/stage.h"
#include "sgslam/config/config.h"
#include "sgslam/features/orb_extractor.h"
#include "sgslam/io/trajectory.h"
#include "sgslam/io/tum_dataset.h"
#include "sgslam/loop/loop_closer.h"
#include "sgslam/map/map.h"
#include "sgslam/mapfile/map_data.h"
#include "sgslam/mapping/global_ba.h"
#include "sgslam/mapping/local_mapper.h"
#include "sgslam/movers/mover_tracker.h"
#include "sgslam/movers/tracks_file.h"
#include "sgslam/semantic/semantic_mapper.h"
#include "sgslam/system/cpu_budget.h"
#include "sgslam/system/dynamic_stage.h"
#include "sgslam/system/snapshot.h"
#include "sgslam/tracking/tracker.h"

namespace sgslam {

struct FrameReport {
  std::size_t index = 0;
  Timestamp t = 0;
  TrackState state = TrackState::kNotInitialized;
  int features = 0, matches = 0, inliers = 0;
  int trusted = 0;  // inliers whose map points are trusted to set the pose (tracking/trusted_pose.h)
  bool keyframe = false;
  int map_keyframes = 0, map_points = 0;  // the map's size after this frame
  double rss_mib = 0;                     // the process's resident memory after this frame
  // Dynamic feature rejection (zeros in mode none): keypoints kept, rejected by
  // the epipolar test, by the boxes alone, by the RGB-D check.
  int kept = 0, rejected_geometry = 0, rejected_semantics = 0, rejected_depth = 0;
  int detections = 0;
  int carried = 0;               // boxes of missed moving objects carried over (dynamic/box_carry.h)
  int predicted = 0;             // mover tracks' predicted boxes given to Algorithm 1 (R12)
  int movers = 0;                // confirmed mover tracks after this frame
  double movers_ms = 0;          // the mover tracker: the predicted boxes and the update
  int followed = 0;              // between detector frames (detector.stride): the last boxes moved with the flow
  int budget_level = 0;          // the CPU budget's throttle after this frame (budget.cores; system/cpu_budget.h)
  std::vector<Detection> boxes;  // this frame's detections, without the carried (written to detections.txt)
  bool detector_late = false;  // tracking stopped waiting: geometry-only frame
  double detector_ms = 0;      // inference time of this frame (detector thread)
  double wait_ms = 0;          // time tracking waited for the detections
  double reject_ms = 0;        // LK flow + F + Algorithm 1
  double extract_ms = 0, track_ms = 0, total_ms = 0;
  // The keypoints (raw pixels) and their labels (1 = rejected as dynamic), for
  // scoring against ground-truth masks; callers drop them after use.
  std::vector<cv::Point2f> keypoints;
  std::vector<std::uint8_t> rejected;
};

class SlamSystem {
 public:
  // detector: the object detector for modes semantic and sg (may be null).
  SlamSystem(const Config& config, bool sequential, std::unique_ptr<Detector> detector = nullptr);
  ~SlamSystem();
  SlamSystem(const SlamSystem&) = delete;
  SlamSystem& operator=(const SlamSystem&) = delete;

  FrameReport Process(const RgbdImages& images);
  // Localisation only (Tracker::SetLocalizationOnly): frames are tracked in the map
  // without adding to it, so local mapping, loop closing and the semantic map get
  // no new keyframe; those made before the switch are still mapped. Call between
  // Process() calls, or before the first one for a map made elsewhere. The final
  // bundle adjustment is skipped in this mode, so the map stays the one the frames
  // were localised in. From the thread that calls Process().
  void SetLocalizationOnly(bool on) { tracker_.SetLocalizationOnly(on); }
  bool localization_only() const { return tracker_.localization_only(); }
  // The frame at which the map reached mapping.max_keyframes and stopped growing.
  std::optional<std::size_t> map_full_at() const { return map_full_at_; }
  // Lets local mapping finish the queued keyframes, stops its thread and runs the
  // final bundle adjustment (mapping.final_ba_iterations). The destructor stops
  // without that adjustment.
  void Finish();

  // Every tracked frame, T_w_c, placed relative to its reference keyframe's final pose.
  Trajectory FrameTrajectory() const;
  Trajectory KeyFrameTrajectory() const;
  // Every tracked frame, T_w_c, as tracking output it at the time (what a robot got live).
  Trajectory OnlineTrajectory() const;
  std::vector<Eigen::Vector3d> MapPointPositions() const;
  std::size_t NumKeyFrames() const;
  // Map consistency problems (empty when consistent); call after Finish().
  std::vector<std::string> CheckMap() const;
  std::vector<MappingStats> mapping_stats() const;
  // The global bundle adjustment Finish() ran (mapping.final_ba_iterations > 0).
  const std::optional<MappingStats>& final_ba() const { return final_ba_; }
  // One report per keyframe the loop closer looked at (loop.enabled).
  std::vector<LoopReport> loop_reports() const;
  // The global bundle adjustments that followed loop closures (aborted ones too).
  struct GlobalBaReport {
    int keyframes = 0, points = 0;
    double ms = 0;
    bool aborted = false;
  };
  std::vector<GlobalBaReport> global_ba_reports() const;
  bool place_recognition() const { return places_ != nullptr; }
  DetectionWorkerStats detector_stats() const { return dynamic_.detector_stats(); }
  // budget.cores: the controller (its level and windows), from the Process() thread.
  const CpuBudget& cpu_budget() const { return budget_; }
  // The mover tracks at every tracked frame, in the frame of FrameTrajectory() (the
  // map's later corrections applied as to the frame's pose); empty in mode none.
  std::vector<movers::TrackLine> MoverTracks() const;
  // Null in mode none.
  const movers::MoverTracker* mover_tracker() const { return movers_.get(); }

  // The semantic map (semantic.enabled), after Finish(): the static dense cloud in
  // the map frame, the objects, the OctoMap. Null / empty when disabled.
  const SemanticMapper* semantic() const { return semantic_.get(); }
  SemanticMapper* semantic() { return semantic_.get(); }
  // T_out_map: the frame objects are expressed (and boxed) in; cloud: map frame.
  // The objects alone, in the frame T_out_map * map (the semantic map's; none without it).
  std::vector<ObjectEstimate> ExportObjects(const SE3& T_out_map = SE3()) const;
  void ExportSemantic(std::vector<Eigen::Vector3d>& cloud, std::vector<Rgb>& colours,
                      std::vector<ObjectEstimate>& objects, const SE3& T_out_map = SE3()) const;
  // Snapshots for observers (a viewer, a ROS node; system/snapshot.h). Enable before
  // the first Process(); LatestFrame() (null before the first frame) and
  // SnapshotMap() may then be called from any thread. Off, nothing is copied.
  void EnableSnapshots();
  std::shared_ptr<const FrameSnapshot> LatestFrame() const;
  MapSnapshot SnapshotMap() const;

  // Map reuse (mapfile/). LoadMap: before the first Process(), into the empty map;
  // needs place recognition; throws InputError naming `what` when the map does not
  // suit this run (camera, ORB pyramid, vocabulary), and then the system is left as
  // it was. The first frame is then relocalised in the map.
  void LoadMap(const mapfile::MapData& data, const std::string& what);
  // Writes the whole map to path, atomically, without stopping tracking: the
  // semantic thread hands over its own state after the keyframe it is on (when there
  // is one), then the map is copied and written on a thread of its own
  // (sg-map-saver). Synchronous in sequential mode and after
  // Finish(). A request while a save is in flight is refused (false). Failures are
  // logged; maps_saved() counts the files written.
  bool SaveMap(const std::filesystem::path& path);
  std::size_t maps_saved() const { return maps_saved_; }

  std::string DescribeDetector() const {
    std::string s = dynamic_.DescribeDetector();
    if (semantic_ && semantic_->has_keyframe_detector()) s += "; keyframes also through " + config_.semantic.keyframe_model + " for the map";
    return s;
  }

 private:
  // Process's steps: ORB features and Algorithm 1's labels; tracking; the exported
  // poses; the keyframes to local mapping.
  Frame MakeFrame(std::uint64_t frame_id, const RgbdImages& images, const std::vector<Detection>& predicted,
                  FrameReport& report);
  // The mover tracks after the frame's pose (movers/mover_tracker.h).
  void UpdateMovers(const Frame& frame, const TrackResult& result, const RgbdImages& images, FrameReport& report);
  // The map's size into the report; at mapping.max_keyframes, localisation only.
  void NoteMapSize(FrameReport& report);
  // budget.cores: the controller's verdict after a frame, applied to the detector's
  // stride and the keyframe model's view gate.
  void ApplyBudget(Timestamp t, FrameReport& report);
  TrackResult Track(Frame& frame, FrameReport& report);
  void RecordPoses(const Frame& frame, const TrackResult& result);
  void HandOverKeyFrames(const Frame& frame, const TrackResult& result, const RgbdImages& images,
                         FrameReport& report);
  void PublishFrame(const Frame& frame, const RgbdImages& images, const FrameReport& report);
  // Local mapping of one keyframe, then the semantic thread and loop closing.
  void MapKeyFrame(SemanticInput item, const std::function<bool()>& interrupted);
  void CloseLoops(const std::shared_ptr<KeyFrame>& kf);
  // The global BA after a loop: on its own thread (inline when sequential), applied
  // with local mapping paused; StopGlobalBa aborts it (a new loop, the end) and
  // joins; true when one was running (it may have finished).
  void StartGlobalBa();
  void RunGlobalBa();
  bool StopGlobalBa(bool abort);
  void Stop(bool final_ba);
  void ToSemantic(SemanticInput item);
  // A new keyframe to local mapping (at once when sequential), then to the semantic thread.
  void HandOver(SemanticInput item);

  const Config config_;
  const bool sequential_;
  std::shared_ptr<const Camera> camera_;
  std::shared_ptr<const ScaleLevels> scale_;
  features::OrbExtractor extractor_;
  DynamicStage dynamic_;
  Map map_;
  std::shared_ptr<KeyFrameDatabase> places_;  // place recognition (loop.enabled), else null
  Tracker tracker_;
  LocalMapper mapper_;

  struct PoseRecord {
    std::uint64_t frame_id;
    Timestamp t;
    std::shared_ptr<KeyFrame> reference;
    SE3 T_c_r;     // frame pose relative to the reference keyframe
    SE3 T_w_c_online;  // the pose as tracking output it, before later map corrections
  };
  std::vector<PoseRecord> records_;

  std::unique_ptr<movers::MoverTracker> movers_;  // mode not none
  std::vector<std::uint8_t> moving_;              // the last MakeFrame's DynamicOutcome::moving
  bool fresh_boxes_ = false;                      // and its fresh_boxes
  // A track at a tracked frame, in that frame's camera frame, so that the map's later
  // corrections move it with the frame (MoverTracks).
  struct TrackSample {
    std::size_t record;  // index in records_
    int id;
    std::string class_name;
    Eigen::Vector3d p_c, v_c, extent;
    movers::TrackState state;
  };
  std::vector<TrackSample> track_samples_;
  CpuBudget budget_;            // budget.cores
  bool budget_warned_ = false;  // the budget is below what tracking and mapping need
  std::uint64_t next_frame_id_ = 0;
  std::uint64_t last_keyframe_frame_id_ = 0;  // for the mapping-busy rule (slam_system.cpp)
  std::optional<std::size_t> map_full_at_;     // mapping.max_keyframes reached at this frame
  std::optional<SemanticInput> held_;          // the last frame's keyframe, not yet mapped (TrackResult::keyframe_held)

  std::unique_ptr<SemanticMapper> semantic_;  // fed by local mapping with refined keyframes
  mutable std::mutex stats_mutex_;
  std::vector<MappingStats> mapping_stats_;  // guarded by stats_mutex_
  std::optional<MappingStats> final_ba_;     // set by Finish() when mapping.final_ba_iterations > 0
  std::unique_ptr<LoopCloser> loop_;  // with place recognition
  std::mutex mapping_step_mutex_;  // local mapping holds it per keyframe; a loop correction pauses it with it
  std::vector<LoopReport> loop_reports_;  // guarded by stats_mutex_
  Job global_ba_{"sg-global-ba"};  // started and joined by loop closing (or Stop, after it)
  std::atomic<bool> gba_abort_{false};
  std::vector<GlobalBaReport> gba_reports_;  // guarded by stats_mutex_
  bool finished_ = false;
  // Map saving (SaveMap): one save at a time; the writer thread is started by the
  // thread that copied the map (the semantic one, or this one) under save_mutex_.
  // Copies the map and writes it with the semantic state: in this thread when now
  // (sequential, finished), else on saver_.
  void SaveCaptured(const std::filesystem::path& path, std::optional<SemanticState> semantic,
                    std::uint64_t next_frame_id, bool now);
  std::atomic<bool> saving_{false};
  std::atomic<std::size_t> maps_saved_{0};
  std::mutex save_mutex_;  // guards saver_; never held with another lock
  Job saver_{"sg-map-saver"};
  // The stages, last: their threads stop (Stop, or here) before the members they use go.
  Stage<SemanticInput> mapping_;                // keyframes (with their images) for local mapping
  Stage<std::shared_ptr<KeyFrame>> loops_;      // mapped keyframes for loop closing
  std::atomic<bool> snapshots_{false};
  mutable std::mutex frame_snapshot_mutex_;  // guards latest_frame_
  std::shared_ptr<const FrameSnapshot> latest_frame_;
};

}  // namespace sgslam
