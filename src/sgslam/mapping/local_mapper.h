// Local mapping (ORB-SLAM2's LocalMapping, for RGB-D): for each new keyframe,
// insert it into the map (and the place-recognition database), cull recent points that do not hold up, triangulate new
// points with covisible keyframes, fuse duplicates, run local bundle adjustment and
// cull redundant keyframes.
//
// Threading: Process() runs on the local mapping thread (or inline in sequential
// mode). It reads under Map::mutex() shared and writes under it exclusively, in
// short sections; the optimisation itself runs on copies without the lock.
#pragma once

#include <functional>
#include <list>
#include <memory>

#include "sgslam/loop/keyframe_database.h"
#include "sgslam/map/map.h"
#include "sgslam/mapping/mapping_config.h"
#include "sgslam/optim/local_ba.h"

namespace sgslam {

struct MappingStats {
  double ms = 0;
  double insert_ms = 0, triangulate_ms = 0, fuse_ms = 0, ba_ms = 0, cull_ms = 0;
  int local_keyframes = 0, local_points = 0;
  int new_points = 0;
  int fused = 0;
  int culled_points = 0;
  int culled_keyframes = 0;
  bool ba_done = false, ba_aborted = false;
};

class LocalMapper {
 public:
  // close_depth: m, the close/far limit of depth points (CameraConfig::close_depth_m).
  // places: the place-recognition database each keyframe enters with its bag of
  // words once inserted, and leaves when culled (null: none).
  LocalMapper(const MappingConfig& config, double close_depth, Map& map,
              std::shared_ptr<KeyFrameDatabase> places = nullptr);

  // `interrupted` is polled during the expensive steps: true when another
  // keyframe waits, so fusion and BA are skipped or aborted (ORB-SLAM2).
  MappingStats Process(const std::shared_ptr<KeyFrame>& kf, const std::function<bool()>& interrupted);

  // Bundle adjustment of the whole map, every keyframe free but the first, with
  // mapping.final_ba_iterations per stage. Run once after the last keyframe was
  // mapped (nothing else may touch the map then).
  MappingStats GlobalBundleAdjustment();

 private:
  void InsertKeyFrame(const std::shared_ptr<KeyFrame>& kf);
  int CullRecentPoints(const std::shared_ptr<KeyFrame>& kf);
  int CreateNewMapPoints(const std::shared_ptr<KeyFrame>& kf);
  int SearchInNeighbors(const std::shared_ptr<KeyFrame>& kf);
  bool LocalBundleAdjustment(const std::shared_ptr<KeyFrame>& kf, const std::function<bool()>& interrupted,
                             MappingStats& stats);
  bool AdjustKeyFrames(const std::vector<std::shared_ptr<KeyFrame>>& free, const optim::BaOptions& options,
                       const std::function<bool()>& interrupted, MappingStats& stats);
  int CullKeyFrames(const std::shared_ptr<KeyFrame>& kf);

  const MappingConfig config_;
  Map& map_;
  const std::shared_ptr<KeyFrameDatabase> places_;
  const double th_depth_;  // m, close/far limit of depth points
  std::list<std::shared_ptr<MapPoint>> recent_points_;
};

}  // namespace sgslam
