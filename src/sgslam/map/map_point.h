// A 3-D point of the sparse map (ORB-SLAM2's MapPoint).
//
// Threading: fields marked [map] are guarded by Map::mutex(): read them under a
// shared lock, write them under an exclusive lock. The counters are atomic (tracking
// bumps them under a shared lock). `track` is touched by the tracking thread only,
// `mapping` by the local mapping thread only.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "sgslam/common/time.h"
#include "sgslam/map/features.h"

namespace sgslam {

class KeyFrame;
class Map;

// The id of a tracking-only point that is never in the map (Tracker::TrackOdometry).
constexpr std::uint64_t kTemporaryPoint = std::numeric_limits<std::uint64_t>::max();

class MapPoint {
 public:
  struct Observation {
    std::weak_ptr<KeyFrame> keyframe;
    std::size_t index = 0;  // keypoint index in that keyframe
    bool stereo = false;    // the keypoint has depth: counts twice
  };

  MapPoint(std::uint64_t id, const Eigen::Vector3d& p_w, const std::shared_ptr<KeyFrame>& reference);

  // What a saved map keeps of a point beyond its position and observations
  // (mapfile/): its appearance and tracking's counts, restored exactly.
  struct Appearance {
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    std::array<std::uint8_t, 32> descriptor{};
    double min_distance = 0, max_distance = 0;  // without the tolerance
    int visible = 1, found = 1;
  };
  // A point loaded from a saved map; its observations and reference are added after.
  MapPoint(std::uint64_t id, std::uint64_t first_keyframe_id, Timestamp created_t, const Eigen::Vector3d& p_w,
           const Appearance& appearance);
  Appearance appearance() const;
  void RestoreReference(const std::shared_ptr<KeyFrame>& reference) { reference_ = reference; }

  const std::uint64_t id;
  const std::uint64_t first_keyframe_id;
  const Timestamp created_t;  // of the keyframe that made it (the age trust is measured by)

  // [map] geometry and appearance.
  const Eigen::Vector3d& position() const { return p_w_; }
  void SetPosition(const Eigen::Vector3d& p_w) { p_w_ = p_w; }
  const Eigen::Vector3d& normal() const { return normal_; }  // mean viewing direction (unit)
  const std::uint8_t* descriptor() const { return descriptor_; }
  double min_distance() const { return 0.8 * min_distance_; }  // with ORB-SLAM2's tolerance
  double max_distance() const { return 1.2 * max_distance_; }
  // Pyramid level a keypoint of this point should have when seen from `distance`.
  int PredictScale(double distance, const ScaleLevels& scale) const;

  // [map] observations, ordered by keyframe id (deterministic iteration).
  const std::map<std::uint64_t, Observation>& observations() const { return observations_; }
  // Stereo/depth observations count twice, as in ORB-SLAM2.
  int num_observations() const { return num_obs_; }
  void AddObservation(const std::shared_ptr<KeyFrame>& kf, std::size_t index);
  // Returns true when the point is left with too few observations (caller sets it bad).
  bool EraseObservation(std::uint64_t keyframe_id);
  int IndexIn(std::uint64_t keyframe_id) const;  // -1 when not observed there
  std::shared_ptr<KeyFrame> reference_keyframe() const { return reference_.lock(); }

  // [map] lifecycle. SetBad detaches the point from every keyframe that sees it
  // and removes it from the map.
  bool bad() const { return bad_; }
  void SetBad(Map& map);
  // Moves every observation to `other` (a duplicate being fused) and sets this bad.
  void ReplaceWith(const std::shared_ptr<MapPoint>& other, Map& map);
  std::shared_ptr<MapPoint> replaced() const { return replaced_; }

  // [map] recomputed after observations change (ORB-SLAM2's descriptor selection:
  // the observed descriptor with the least median distance to the others).
  void UpdateDescriptor();
  void UpdateNormalAndDepth();

  // How often the point was predicted in view vs actually matched by tracking.
  void IncreaseVisible(int n = 1) { visible_.fetch_add(n, std::memory_order_relaxed); }
  void IncreaseFound(int n = 1) { found_.fetch_add(n, std::memory_order_relaxed); }
  double FoundRatio() const {
    const int v = visible_.load(std::memory_order_relaxed);
    return v > 0 ? static_cast<double>(found_.load(std::memory_order_relaxed)) / v : 0.0;
  }

  // Tracking thread scratch: the projection computed by Frame::IsInFrustum.
  struct TrackScratch {
    bool in_view = false;
    double u = 0, v = 0, u_right = -1, view_cos = 0;
    int predicted_level = 0;
    std::uint64_t local_for_frame = 0;  // already in the local map of this frame
    std::uint64_t last_frame_seen = 0;  // matched in this frame
    // Trust (tracking/trusted_pose.h): whether the point may set a frame's pose,
    // and the late inlier matches that earn it.
    bool trusted = false;
    int trust_hits = 0;
  } track;
  // Local mapping thread scratch.
  struct MappingScratch {
    std::uint64_t ba_local_for_kf = 0;
    std::uint64_t fuse_candidate_for_kf = 0;
  } mapping;

 private:
  Eigen::Vector3d p_w_;
  Eigen::Vector3d normal_ = Eigen::Vector3d::Zero();
  std::uint8_t descriptor_[32] = {};
  double min_distance_ = 0, max_distance_ = 0;
  std::map<std::uint64_t, Observation> observations_;
  int num_obs_ = 0;
  std::weak_ptr<KeyFrame> reference_;
  bool bad_ = false;
  std::shared_ptr<MapPoint> replaced_;
  std::atomic<int> visible_{1}, found_{1};
};

}  // namespace sgslam
