// The map: owner of every keyframe and map point.
//
// Lock order and rules (docs/architecture.md, "Locks and atomics"): one map-level shared_mutex guards every
// [map] field of keyframes and map points. Tracking reads under a shared lock and
// takes it exclusively only to insert a keyframe; local mapping reads under a
// shared lock and writes (new points, fusion, culling, BA results) under an
// exclusive lock held briefly; optimisation itself runs on copies without a lock.
// While it is held, tracking, mapping and loop closing take only the
// place-recognition database's mutex (a leaf); the export after Finish() also takes
// the semantic mapper's, which no other thread holds by then. SlamSystem's mapping
// step mutex is taken before it.
// Per-entity mutexes were tried in ORB-SLAM2 and led to its shutdown and reset
// races; one readers-writer lock is simpler and TSan-clean at our scale.
#pragma once

#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <shared_mutex>
#include <vector>

#include "sgslam/map/keyframe.h"
#include "sgslam/map/map_point.h"

namespace sgslam {

class Map {
 public:
  Map() = default;
  ~Map();
  Map(const Map&) = delete;
  Map& operator=(const Map&) = delete;

  std::shared_mutex& mutex() const { return mutex_; }

  std::uint64_t NewKeyFrameId() { return next_keyframe_id_++; }
  std::uint64_t NewMapPointId() { return next_point_id_++; }
  // A map loaded from a file (mapfile/): new ids continue after its own.
  void RestoreIds(std::uint64_t next_keyframe_id, std::uint64_t next_point_id) {
    next_keyframe_id_ = next_keyframe_id;
    next_point_id_ = next_point_id;
  }
  std::uint64_t next_keyframe_id() const { return next_keyframe_id_; }
  std::uint64_t next_point_id() const { return next_point_id_; }

  // [map] membership; ordered by id so every traversal is deterministic.
  void AddKeyFrame(const std::shared_ptr<KeyFrame>& kf) {
    keyframes_[kf->id] = kf;
    pending_.erase(kf->id);
  }
  // [map] A keyframe tracking made, with its points in the map, that local mapping
  // has not inserted yet (AddKeyFrame ends that).
  void AddPending(const std::shared_ptr<KeyFrame>& kf) { pending_[kf->id] = kf; }
  const std::map<std::uint64_t, std::shared_ptr<KeyFrame>>& pending() const { return pending_; }
  void EraseKeyFrame(std::uint64_t id) { keyframes_.erase(id); }
  void AddMapPoint(const std::shared_ptr<MapPoint>& p) { points_[p->id] = p; }
  void EraseMapPoint(std::uint64_t id) { points_.erase(id); }
  const std::map<std::uint64_t, std::shared_ptr<KeyFrame>>& keyframes() const { return keyframes_; }
  const std::map<std::uint64_t, std::shared_ptr<MapPoint>>& map_points() const { return points_; }

  // [map] Loop corrections so far: a pose computed before the count changed is
  // placed again relative to its reference keyframe.
  void NoteCorrection() { ++corrections_; }
  std::uint64_t corrections() const { return corrections_; }

  // Breaks every link between entities so that shared ownership cycles cannot leak.
  void Clear();

 private:
  mutable std::shared_mutex mutex_;
  std::atomic<std::uint64_t> next_keyframe_id_{0}, next_point_id_{0};
  std::map<std::uint64_t, std::shared_ptr<KeyFrame>> keyframes_;
  std::map<std::uint64_t, std::shared_ptr<MapPoint>> points_;
  std::map<std::uint64_t, std::shared_ptr<KeyFrame>> pending_;
  std::uint64_t corrections_ = 0;
};

// [map] Keyframes tracking made that local mapping has not inserted yet (their
// points are in the map, they are not), without the culled. Ordered by id.
std::vector<std::shared_ptr<KeyFrame>> PendingKeyFrames(const Map& map);

}  // namespace sgslam
