// Tracking (ORB-SLAM2's Tracking for RGB-D, split into small steps): map
// initialisation, constant-velocity tracking, reference-keyframe tracking,
// local-map tracking, the keyframe decision and keyframe creation.
//
// Threading: called by one thread (the tracking thread, or the only thread in
// sequential mode). Reads the map under Map::mutex() shared and takes it
// exclusively only to create a keyframe and its new points.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "sgslam/camera/rolling_shutter.h"
#include "sgslam/camera/camera_config.h"
#include "sgslam/loop/keyframe_database.h"
#include "sgslam/map/frame.h"
#include "sgslam/map/map.h"
#include "sgslam/tracking/local_map.h"
#include "sgslam/tracking/tracking_config.h"
#include "sgslam/tracking/trusted_pose.h"

namespace sgslam {

// kOk: tracked in the map; kOdometry: the map could not be matched, the pose comes
// from the frame before (visual odometry on its kept keypoints with depth: the map
// is not touched, no keyframe is made; docs/tracking-states.md); kLost: no pose.
enum class TrackState { kNotInitialized, kOk, kOdometry, kLost };
const char* ToString(TrackState state);
inline bool HasPose(TrackState state) { return state == TrackState::kOk || state == TrackState::kOdometry; }

struct TrackResult {
  TrackState state = TrackState::kNotInitialized;
  int matches = 0;  // map points matched before the last pose optimisation
  int inliers = 0;  // after it
  int trusted = 0;  // of the inliers, map points trusted to set the pose (trusted_pose.h)
  std::shared_ptr<KeyFrame> new_keyframe;  // for local mapping, when one was made
  std::shared_ptr<KeyFrame> reference;     // the frame's reference keyframe (state ok)
  SE3 T_c_r;                               // the frame's pose relative to it, as tracked
  // tracking.refinements.frame_velocity_central: the previous frame's pose fitted again once
  // this frame's pose is known (Tracker::RefinePrevious); for the exported
  // trajectory only, tracking goes on from the pose it had.
  struct Refined {
    std::uint64_t frame_id = 0;
    SE3 T_c_w;
  };
  std::optional<Refined> previous_refined;
  // new_keyframe stays with tracking for one frame, because the next frame changes
  // it; its points are in the map meanwhile. The caller hands it to local mapping
  // after the next Track call (or at the end of the sequence). Two reasons:
  // - a rolling shutter with tracking.refinements.keyframe_velocity_central: the next Track
  //   corrects its keypoints with the angular velocity of the poses on either side
  //   (central difference, no lag) instead of the one fitted within its own frame,
  //   which lags the truth by about 1.5 frames, and moves the points it made (the
  //   map's first keyframe, which had no velocity at all, gets the one of the step
  //   to the next frame);
  // - its frame was judged by its boxes alone (Frame::judged_again): the next frame
  //   judges its keypoints again (ConfirmStaticInFirstKeyFrame).
  bool keyframe_held = false;
};

class Tracker {
 public:
  // orb_features: the ORB budget per frame (the map's first frame needs at most
  // half of it with depth); camera: the rolling-shutter readout, the close range;
  // places: the place-recognition database a lost camera is relocalised with
  // (null: only keyframes near its last pose are tried).
  Tracker(const TrackingConfig& config, int orb_features, const CameraConfig& camera, Map& map,
          std::shared_ptr<const KeyFrameDatabase> places = nullptr);

  // mapping_idle / mapping_full: whether local mapping is free, and whether its
  // queue is full (no keyframe is made then); the keyframe decision takes both
  // into account.
  TrackResult Track(Frame& frame, bool mapping_idle, bool mapping_full);

  // Localisation only (ORB-SLAM2's localisation mode): frames are tracked against
  // the map and relocalised in it when lost, but no keyframe or map point is made:
  // poses and points are only read (the points' match counts and trust still
  // count). Before the first frame, the map is one made elsewhere (loaded): the
  // first frames are relocalised in it instead of starting a map. Between Track calls.
  void SetLocalizationOnly(bool on) { localization_only_ = on; }
  // Which of a frame's boxes hold a mover (a moving-object class, a carried box, a
  // track's predicted box): the odometry fallback makes no temporary point in them.
  using MoverBoxFn = std::function<bool(const Detection&)>;
  void SetMoverBoxes(MoverBoxFn fn) { mover_box_ = std::move(fn); }
  bool localization_only() const { return localization_only_; }


  // The map's first keyframe, when its keypoints were judged by their detection
  // boxes alone (the first frame has no flow): rejected keypoints with depth that
  // now_static marks (one flag per keypoint, from DynamicStage's second judgment)
  // are kept after all and become trusted map points, like the keyframe's others.
  // Call after the next frame is labelled and before it is tracked, while the
  // keyframe has not gone to local mapping. Returns the keypoints cleared; 0 when
  // the map has moved on from its first keyframe.
  int ConfirmStaticInFirstKeyFrame(const std::vector<std::uint8_t>& now_static);

  // The map was loaded from a file (mapfile/): no initialisation; the next frame
  // is relocalised in it, as after a loss.
  void StartInMap() { state_ = TrackState::kLost; }

  TrackState state() const { return state_; }
  // The next frame's pose as the motion model predicts it (the last frame's
  // without a velocity); none unless tracking is OK.
  std::optional<SE3> PredictedPose() const {
    if (!HasPose(state_) || !last_frame_.has_pose) return std::nullopt;
    return has_velocity_ ? velocity_ * last_frame_.T_c_w : last_frame_.T_c_w;
  }
  // The camera-frame angular velocity (rad/s) of that prediction, for the rolling
  // shutter correction of the next frame's keypoints; none when there is none.
  std::optional<Eigen::Vector3d> PredictedAngularVelocity() const {
    if (!HasPose(state_) || !has_velocity_) return std::nullopt;
    return AngularVelocity(velocity_, velocity_dt_);
  }

 private:
  bool Initialize(Frame& frame, TrackResult& result);
  // Motion model, reference keyframe or relocalisation, then the local map, under the
  // map's shared lock; sets result.reference and T_c_r, and the map's corrections then.
  bool TrackAgainstMap(Frame& frame, TrackResult& result, std::uint64_t& corrections);
  bool TrackWithMotionModel(Frame& frame, TrackResult& result);
  bool TrackReferenceKeyFrame(Frame& frame, const std::shared_ptr<KeyFrame>& keyframe, TrackResult& result);
  // A lost frame back into the map: Recover, then (with place recognition) Relocalise.
  bool RegainMap(Frame& frame, TrackResult& result);
  // The keyframes near where the camera was lost, by descriptor and PnP RANSAC.
  bool Recover(Frame& frame, TrackResult& result);
  // The visual-odometry fallback (TrackState::kOdometry): the last frame's kept
  // keypoints with depth that match no map point become temporary points
  // (ORB-SLAM2's localisation mode does the same), matched by projection from the
  // motion model's pose and fitted; false below kMinOdometryInliers. Map lock held.
  bool TrackOdometry(Frame& frame, TrackResult& result);
  // ORB-SLAM2's relocalisation: candidates from the place-recognition database,
  // bag-of-words matching, PnP RANSAC, pose optimisation and a guided search.
  bool Relocalise(Frame& frame, TrackResult& result);
  bool RelocaliseWith(Frame& frame, const KeyFrame& candidate, const vocab::BowData& bow);
  bool TrackLocalMap(Frame& frame, TrackResult& result);
  // With a rolling-shutter camera: fits the frame's pose and angular velocity
  // together on its inliers (the prediction lags by a frame), corrects its
  // keypoints with that velocity and fits the pose again.
  void RefineRollingShutter(Frame& frame);
  // Pose-only optimisation of the frame's matches; drops outliers; returns the
  // number of inliers that are map points.
  int OptimizePose(Frame& frame);
  static void DiscardOutliers(Frame& frame);
  bool NeedNewKeyFrame(const Frame& frame, int inliers, bool mapping_idle, bool mapping_full) const;
  // T_c_r: the frame relative to reference_kf_ as tracked; corrections: the map's
  // loop corrections then (a correction since moves the frame with its reference).
  std::shared_ptr<KeyFrame> CreateKeyFrame(Frame& frame, const SE3& T_c_r, std::uint64_t corrections);
  // Creates map points from the depth of keypoints without one (close first).
  int AddDepthPoints(Frame& frame, const std::shared_ptr<KeyFrame>& kf, bool all);

  const TrackingConfig config_;
  const CameraConfig camera_;
  const int min_init_points_;          // keypoints with depth the map's first frame needs
  const int rejected_match_distance_;  // bits, refinements.rejected_matches; 0: never
  const TrustOptions trust_;
  Map& map_;
  MoverBoxFn mover_box_;
  const std::shared_ptr<const KeyFrameDatabase> places_;
  LocalMap local_map_;
  TrackState state_ = TrackState::kNotInitialized;
  bool localization_only_ = false;
  Frame last_frame_;
  bool has_velocity_ = false;
  SE3 velocity_;  // T_cur_last of the last two tracked frames
  double velocity_dt_ = 0;  // s between them
  std::shared_ptr<KeyFrame> reference_kf_;
  SE3 last_T_c_r_;  // last frame's pose relative to its reference keyframe
  std::uint64_t last_keyframe_frame_id_ = 0;
  const double th_depth_;  // m, the close/far limit of depth points (ORB-SLAM2's ThDepth)
  // A tracked frame (id, time, pose), for the central difference. Kept relative to
  // its reference keyframe, as last_frame_ is: local BA may move the map before the
  // next frame, and a central difference across two versions of the map would
  // measure the move as a turn.
  struct Before {
    std::uint64_t id = 0;
    Timestamp t = 0;
    SE3 T_c_w;  // when the keyframe is gone
    std::shared_ptr<KeyFrame> reference;
    SE3 T_c_r;
    SE3 Pose() const { return reference && !reference->bad() ? T_c_r * reference->T_c_w() : T_c_w; }  // map lock held
  };
  // The tracked frame before last_frame_ when they are adjacent; for the map's
  // first keyframe, that frame itself (the step to the next frame is then all there is).
  std::optional<Before> before_last_;
  Before BeforeOf(const Frame& frame);  // takes the map's shared lock
  // Whether either central difference is on (before_last_ is kept only then).
  bool UsesCentralDifference() const;
  TrackResult TrackFrame(Frame& frame, bool mapping_idle, bool mapping_full);  // Track but keyframe_held
  // With a rolling shutter and tracking.refinements.keyframe_velocity_central (TrackResult::keyframe_held).
  bool KeyFramesWait() const;
  // last_frame_'s keyframe, held for this frame's velocity (KeyFramesWait).
  std::shared_ptr<KeyFrame> waiting_;
  // Corrects the waiting keyframe with next, the frame after it (tracked), and
  // before, the frame before it; false when it could not (no velocity, or the
  // keyframe was culled).
  bool CorrectWaitingKeyFrame(const std::shared_ptr<KeyFrame>& kf, const Before& before, const Frame& next);
  // tracking.refinements.frame_velocity_central: last_frame_'s keypoints corrected with the
  // angular velocity of the poses on either side (before_last_ and next, both
  // tracked and adjacent), and its pose fitted again to its matches; none when
  // it cannot be. Leaves last_frame_ as it is.
  std::optional<SE3> RefinePrevious(const Frame& next);
  // Frames the initialisation waited for more kept keypoints with depth (Initialize).
  static constexpr int kMaxInitDeferrals = 5;
  int init_deferred_ = 0;
  static constexpr int kInitWarnFrames = 30;  // frames without a start before a warning
  int init_failures_ = 0;
  int best_init_depth_points_ = 0;
};

}  // namespace sgslam
