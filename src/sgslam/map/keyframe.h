// A keyframe: a frame kept in the map, with its pose, the map points its keypoints
// observe, the covisibility graph and the spanning tree (ORB-SLAM2's KeyFrame).
//
// Threading: fields marked [map] are guarded by Map::mutex() (shared lock to read,
// exclusive to write). `features` is immutable once local mapping has the keyframe
// (until then only the tracking thread sees it: ReplaceFeatures). Graph links to
// other keyframes are weak (back-references); the Map owns keyframes, a keyframe
// owns its map points.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <vector>

#include "sgslam/common/se3.h"
#include "sgslam/common/time.h"
#include "sgslam/map/features.h"
#include "sgslam/vocab/bow_vector.h"

namespace sgslam {

class MapPoint;
class Map;

class KeyFrame : public std::enable_shared_from_this<KeyFrame> {
 public:
  KeyFrame(std::uint64_t id, std::uint64_t frame_id, Timestamp t, std::shared_ptr<const Features> features,
           const SE3& T_c_w);

  const std::uint64_t id;
  const std::uint64_t frame_id;
  const Timestamp t;
  // Immutable once local mapping has the keyframe; until then the tracker may
  // replace it (ReplaceFeatures, Tracker::CorrectWaitingKeyFrame).
  std::shared_ptr<const Features> features;
  // [map, exclusive] Before the keyframe goes to local mapping only: the same
  // keypoints, corrected again (same count and order).
  void ReplaceFeatures(std::shared_ptr<const Features> corrected);

  // [map] The bag of words of its descriptors (vocab/), set once by local mapping
  // before the keyframe enters the place-recognition database; null before, and
  // without a vocabulary. Immutable once set.
  std::shared_ptr<const vocab::BowData> bow;

  // [map] pose.
  const SE3& T_c_w() const { return T_c_w_; }
  SE3 T_w_c() const { return T_c_w_.Inverse(); }
  Eigen::Vector3d center() const { return T_w_c_translation_; }
  void SetPose(const SE3& T_c_w);

  // [map] map points by keypoint index (nullptr where none).
  const std::vector<std::shared_ptr<MapPoint>>& map_points() const { return map_points_; }
  const std::shared_ptr<MapPoint>& map_point(std::size_t i) const { return map_points_[i]; }
  void SetMapPoint(std::size_t i, std::shared_ptr<MapPoint> point) { map_points_[i] = std::move(point); }
  void EraseMapPoint(std::size_t i) { map_points_[i].reset(); }
  // Good map points seen by at least min_observations keyframes.
  int TrackedMapPoints(int min_observations) const;

  // [map] covisibility graph: weight = number of shared map points.
  void UpdateConnections();  // recomputes this keyframe's edges from its map points
  std::vector<std::shared_ptr<KeyFrame>> Covisibles(std::size_t n = SIZE_MAX) const;  // best first
  std::vector<std::shared_ptr<KeyFrame>> CovisiblesWithWeight(int min_weight) const;
  int Weight(std::uint64_t other_id) const;
  void AddConnection(const std::shared_ptr<KeyFrame>& other, int weight);
  // Every keyframe with an edge, weak ones too (ORB-SLAM2's GetConnectedKeyFrames).
  std::vector<std::uint64_t> ConnectedIds() const;
  // The covisibility order Covisibles() walks (id, weight): the strong edges after
  // this keyframe's own UpdateConnections, every edge after a neighbour's change.
  std::vector<std::pair<std::uint64_t, int>> CovisibleOrder() const;
  // A keyframe loaded from a saved map (mapfile/): its edges and their order as saved.
  using Edges = std::vector<std::pair<std::shared_ptr<KeyFrame>, int>>;
  void RestoreConnections(const Edges& connections, const Edges& order);

  // [map] Loop edges (a verified loop closed between the two), kept for later
  // pose-graph optimisations; a keyframe with one is never culled.
  void AddLoopEdge(const std::shared_ptr<KeyFrame>& other) { loop_edges_[other->id] = other; }
  std::vector<std::shared_ptr<KeyFrame>> LoopEdges() const;
  void EraseConnection(std::uint64_t other_id);

  // [map] spanning tree (set by the first UpdateConnections: the best covisible).
  std::shared_ptr<KeyFrame> parent() const { return parent_.lock(); }
  std::vector<std::shared_ptr<KeyFrame>> children() const;
  void SetParent(const std::shared_ptr<KeyFrame>& parent);

  // [map] culling. SetBad unlinks the keyframe from its points and neighbours and
  // hands its children to other parents; the pose relative to the parent is kept
  // so that frames tracked against this keyframe can still be placed.
  bool bad() const { return bad_; }
  void SetBad(Map& map);
  const SE3& T_c_parent() const { return T_c_parent_; }
  // The parent at the time of culling, held strongly so that the chain from a
  // culled keyframe to a live one never breaks (parents are older: no cycles).
  const std::shared_ptr<KeyFrame>& parent_when_culled() const { return parent_when_culled_; }
  // A culled keyframe loaded from a saved map (mapfile/), which only anchors the
  // semantic data made from it: bad, placed relative to parent.
  void RestoreCulled(std::shared_ptr<KeyFrame> parent, const SE3& T_c_parent);
  // [map] The pose now, for a culled keyframe too: placed on the live keyframe its
  // chain of parents ends at (ORB-SLAM2's trajectory export).
  SE3 PlacedT_c_w() const;

  // Local mapping / tracking scratch (each touched by one thread only).
  std::uint64_t ba_local_for_kf = 0, ba_fixed_for_kf = 0;  // local mapping
  std::uint64_t track_local_for_frame = 0;                 // tracking

 private:
  void UpdateOrder();
  void AddChild(const std::shared_ptr<KeyFrame>& child);
  void EraseChild(std::uint64_t child_id);

  SE3 T_c_w_;
  Eigen::Vector3d T_w_c_translation_;
  std::vector<std::shared_ptr<MapPoint>> map_points_;
  std::map<std::uint64_t, std::pair<std::weak_ptr<KeyFrame>, int>> connections_;
  std::vector<std::pair<int, std::weak_ptr<KeyFrame>>> ordered_;  // weight desc, id asc
  std::weak_ptr<KeyFrame> parent_;
  std::map<std::uint64_t, std::weak_ptr<KeyFrame>> children_;
  std::map<std::uint64_t, std::weak_ptr<KeyFrame>> loop_edges_;
  bool has_parent_ = false;
  bool bad_ = false;
  SE3 T_c_parent_;
  std::shared_ptr<KeyFrame> parent_when_culled_;
};

}  // namespace sgslam
