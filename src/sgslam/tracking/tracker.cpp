#include "sgslam/tracking/tracker.h"

#include <algorithm>
#include <mutex>
#include <numeric>
#include <shared_mutex>

#include <spdlog/spdlog.h>

#include "sgslam/geometry/pnp.h"
#include "sgslam/matching/matcher.h"
#include "sgslam/optim/pose_optimizer.h"
#include "sgslam/optim/rolling_shutter_pose.h"

namespace sgslam {

namespace {

// ORB-SLAM2's RGB-D tracking settings unless a comment says otherwise.
constexpr int kMinInitPoints = 500;           // keypoints with depth needed to start the map (see the constructor)
constexpr double kMotionSearchRadius = 15.0;  // px at level 0, constant-velocity projection search
// factor, local-map projection search (ORB-SLAM2: 3): under fast rotation the
// rolling shutter shifts rows by pixels.
constexpr double kLocalSearchRadius = 5.0;
constexpr double kDescriptorRatio = 0.7;  // best/second-best ratio, reference keyframe matching
constexpr int kMinMotionMatches = 20;     // matches needed to trust the motion model
constexpr int kMinPoseInliers = 10;       // inliers after pose optimisation (motion / reference)
constexpr int kMinLocalInliers = 30;      // inliers after local-map tracking
// The odometry fallback: a pose from the frame before needs this many inliers
// among the temporary points and the map points it matched (half what the local
// map asks for: on the dynamic panel 30 gave a pose to 1 of crowd's 6 lost frames,
// 15 to 3, 12 to all but caught more movers; docs/experiments.md).
constexpr int kMinOdometryInliers = 15;
// Keyframes tried per frame while lost without place recognition (loop.enabled
// false): the newest 5, then the nearest.
constexpr int kRecoverCandidates = 30;
// Trusted map points (refinements.trusted_points, trusted_pose.h): trusted after
// this many inlier matches at least kTrustDelay after their keyframe made them;
// a frame is fitted to them first when it has kTrustMinPoints of them.
constexpr double kTrustDelay = 0.3;  // s
constexpr int kTrustHits = 2;
constexpr int kTrustMinPoints = 20;
// bits: how close a rejected keypoint's descriptor must be to a trusted map point
// that no kept keypoint matched (refinements.rejected_matches); 0: never matched.
constexpr int kRejectedMatchDistance = 50;
constexpr double kRollingShutterPrior = 1.0;  // rad/s, sigma of the refined angular velocity around the predicted one

optim::Intrinsics IntrinsicsOf(const Camera& cam) {
  return {cam.fx(), cam.fy(), cam.cx(), cam.cy(), cam.baseline_fx()};
}

// Keypoint i of f matched to map point p, as the pose optimisers take it.
optim::PoseObservation PoseObservationOf(const Features& f, std::size_t i, const MapPoint& p) {
  optim::PoseObservation o;
  o.p_w = p.position();
  o.uv = {f.keys_un[i].pt.x, f.keys_un[i].pt.y};
  o.u_right = f.u_right[i];
  o.inv_sigma2 = f.scale->inv_sigma2[static_cast<std::size_t>(f.keys_un[i].octave)];
  return o;
}

// The frame's pose from its matched map points (PnP RANSAC on the undistorted keypoints).
std::optional<SE3> PnpOnMatches(const Frame& frame, const geometry::PnpOptions& options) {
  const Features& f = *frame.features;
  std::vector<cv::Point3f> object;
  std::vector<cv::Point2f> image;
  for (std::size_t i = 0; i < frame.map_points.size(); ++i) {
    if (!frame.map_points[i]) continue;
    const Eigen::Vector3d p = frame.map_points[i]->position();
    object.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
    image.push_back(f.keys_un[i].pt);
  }
  const Camera& cam = *f.camera;
  return geometry::SolvePnP(object, image, {cam.fx(), cam.fy(), cam.cx(), cam.cy()}, options);
}

}  // namespace

const char* ToString(TrackState state) {
  switch (state) {
    case TrackState::kNotInitialized: return "not_initialized";
    case TrackState::kOk: return "ok";
    case TrackState::kOdometry: return "odometry";
    case TrackState::kLost: return "lost";
  }
  return "?";
}

// The map starts on a frame with kMinInitPoints keypoints with depth, but never
// needs more than half the ORB budget: not every keypoint has depth (ORB-SLAM2 asks
// for 500 keypoints, with depth or not), and a user may lower orb.features for speed.
Tracker::Tracker(const TrackingConfig& config, int orb_features, const CameraConfig& camera, Map& map,
                 std::shared_ptr<const KeyFrameDatabase> places)
    : config_(config),
      camera_(camera),
      min_init_points_(std::min(kMinInitPoints, std::max(1, orb_features / 2))),
      rejected_match_distance_(config.refinements.rejected_matches ? kRejectedMatchDistance : 0),
      trust_{config.refinements.trusted_points ? kTrustDelay : 0.0, kTrustHits, kTrustMinPoints},
      map_(map),
      places_(std::move(places)),
      th_depth_(camera.close_depth_m()) {}

TrackResult Tracker::Track(Frame& frame, bool mapping_idle, bool mapping_full) {
  TrackResult result = TrackFrame(frame, mapping_idle, mapping_full);
  result.keyframe_held = result.new_keyframe && (KeyFramesWait() || frame.judged_again);
  return result;
}

TrackResult Tracker::TrackFrame(Frame& frame, bool mapping_idle, bool mapping_full) {
  TrackResult result;
  if (state_ == TrackState::kNotInitialized && !localization_only_) {
    if (Initialize(frame, result)) {
      state_ = TrackState::kOk;
      last_frame_ = frame;
    }
    result.state = state_;
    return result;
  }

  std::uint64_t corrections = 0;
  bool ok = TrackAgainstMap(frame, result, corrections);
  // The last frame's keyframe, corrected with this frame's pose; this frame is then
  // fitted again to its corrected points.
  if (waiting_) {
    if (ok && before_last_ && CorrectWaitingKeyFrame(waiting_, *before_last_, frame)) {
      std::shared_lock lock(map_.mutex());
      if (map_.corrections() != corrections) frame.T_c_w = result.T_c_r * reference_kf_->T_c_w();  // a loop since
      OptimizePose(frame);
      result.T_c_r = frame.T_c_w * reference_kf_->T_w_c();
      corrections = map_.corrections();
    }
    waiting_.reset();
  }
  if (ok) {
    if (const auto refined = RefinePrevious(frame)) result.previous_refined = TrackResult::Refined{last_frame_.id, *refined};
  }

  if (!ok && config_.odometry_fallback && last_frame_.has_pose && reference_kf_) {
    std::shared_lock lock(map_.mutex());
    if (TrackOdometry(frame, result)) {
      // A pose, not a map match: the map and the keyframes stay as they are.
      state_ = TrackState::kOdometry;
      frame.has_pose = true;
      frame.reference_kf = reference_kf_;
      result.reference = reference_kf_;
      result.T_c_r = frame.T_c_w * reference_kf_->T_w_c();
      velocity_ = frame.T_c_w * last_frame_.T_c_w.Inverse();
      velocity_dt_ = ToSeconds(frame.t - last_frame_.t);
      has_velocity_ = last_frame_.id + 1 == frame.id;
      last_T_c_r_ = result.T_c_r;
      before_last_.reset();
      last_frame_ = frame;
      result.state = state_;
      return result;
    }
  }
  if (!ok) {
    // Lost: the map stays untouched; the next frame starts from the last good pose.
    state_ = TrackState::kLost;
    has_velocity_ = false;
    frame.has_pose = false;
    result.state = state_;
    return result;
  }
  state_ = TrackState::kOk;
  // Back from odometry: the temporary points the motion model matched are no map
  // points; the keyframe decision and the next frame see only the map's.
  for (auto& p : frame.map_points) {
    if (p && p->id == kTemporaryPoint) p.reset();
  }
  frame.has_pose = true;
  frame.reference_kf = reference_kf_;
  velocity_ = frame.T_c_w * last_frame_.T_c_w.Inverse();
  velocity_dt_ = ToSeconds(frame.t - last_frame_.t);
  has_velocity_ = last_frame_.has_pose && last_frame_.id + 1 == frame.id;  // not across a loss

  bool need_keyframe = false;
  {
    std::shared_lock lock(map_.mutex());
    need_keyframe = !localization_only_ && NeedNewKeyFrame(frame, result.inliers, mapping_idle, mapping_full);
  }
  if (need_keyframe) {
    result.new_keyframe = CreateKeyFrame(frame, result.T_c_r, corrections);
    result.reference = result.new_keyframe;
    result.T_c_r = SE3();
    // Its frame before is last_frame_, which becomes before_last_ below.
    if (KeyFramesWait() && last_frame_.has_pose && last_frame_.id + 1 == frame.id) waiting_ = result.new_keyframe;
  }
  frame.reference_kf = result.reference;
  last_T_c_r_ = result.T_c_r;
  // Outliers of this frame must not seed the next frame's motion search.
  DiscardOutliers(frame);
  before_last_.reset();
  if (UsesCentralDifference() && last_frame_.has_pose && last_frame_.id + 1 == frame.id) {
    before_last_ = BeforeOf(last_frame_);
  }
  last_frame_ = frame;
  result.state = state_;
  return result;
}

bool Tracker::TrackAgainstMap(Frame& frame, TrackResult& result, std::uint64_t& corrections) {
  std::shared_lock lock(map_.mutex());
  // Local BA or a loop correction may have moved the last frame's reference
  // keyframe since: keep the last frame where it sits relative to it (ORB-SLAM2's
  // UpdateLastFrame).
  if (const auto& ref = last_frame_.reference_kf; ref && !ref->bad() && last_frame_.has_pose) {
    last_frame_.T_c_w = last_T_c_r_ * ref->T_c_w();
  }
  bool ok = false;
  if (state_ == TrackState::kOk) {
    ok = ((has_velocity_ && TrackWithMotionModel(frame, result)) || TrackReferenceKeyFrame(frame, reference_kf_, result)) &&
         TrackLocalMap(frame, result);
  } else if (state_ == TrackState::kOdometry) {
    // The last pose came from odometry: the motion model on its map points and
    // temporary points, then the local map; else a place the map knows.
    ok = has_velocity_ && TrackWithMotionModel(frame, result) && TrackLocalMap(frame, result);
    if (!ok) ok = RegainMap(frame, result) && TrackLocalMap(frame, result);
  } else {
    ok = RegainMap(frame, result) && TrackLocalMap(frame, result);
  }
  if (ok) {
    result.reference = reference_kf_;
    result.T_c_r = frame.T_c_w * reference_kf_->T_w_c();
  }
  corrections = map_.corrections();
  return ok;
}

Tracker::Before Tracker::BeforeOf(const Frame& frame) {
  Before b{frame.id, frame.t, frame.T_c_w, frame.reference_kf, frame.T_c_w};
  if (frame.reference_kf) {
    std::shared_lock lock(map_.mutex());
    b.T_c_r = frame.T_c_w * frame.reference_kf->T_w_c();
  }
  return b;
}

bool Tracker::KeyFramesWait() const {
  return config_.refinements.keyframe_velocity_central && camera_.readout > 0;
}

bool Tracker::UsesCentralDifference() const {
  return KeyFramesWait() || (config_.refinements.frame_velocity_central && camera_.readout > 0);
}

bool Tracker::CorrectWaitingKeyFrame(const std::shared_ptr<KeyFrame>& kf, const Before& before, const Frame& next) {
  std::unique_lock lock(map_.mutex());
  if (kf->bad()) return false;
  const auto w = AngularVelocity(next.T_c_w * before.Pose().Inverse(), ToSeconds(next.t - before.t));
  if (!w) return false;
  const std::shared_ptr<const Features> corrected = WithRollingShutterCorrection(*kf->features, *w);
  kf->ReplaceFeatures(corrected);
  // The points it made from its depth (AddDepthPoints) follow their keypoints.
  const SE3 T_w_c = kf->T_w_c();
  const auto& points = kf->map_points();
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto& p = points[i];
    if (p && !p->bad() && p->first_keyframe_id == kf->id && corrected->depth[i] > 0) {
      p->SetPosition(T_w_c * corrected->Unproject(i));
    }
  }
  return true;
}

std::optional<SE3> Tracker::RefinePrevious(const Frame& next) {
  if (!config_.refinements.frame_velocity_central || camera_.readout <= 0) return std::nullopt;
  // before_last_ is adjacent to last_frame_ by construction, except for the map's
  // first frame (its own pose, no central difference).
  if (!before_last_ || before_last_->id + 1 != last_frame_.id || last_frame_.id + 1 != next.id) return std::nullopt;
  std::shared_lock lock(map_.mutex());
  const auto w = AngularVelocity(next.T_c_w * before_last_->Pose().Inverse(), ToSeconds(next.t - before_last_->t));
  if (!w) return std::nullopt;
  // A copy: the motion model and the next search go on from the pose tracking gave
  // it; only the exported trajectory takes the refit (docs/rolling-shutter.md).
  Frame copy = last_frame_;
  copy.features = WithRollingShutterCorrection(*last_frame_.features, *w);
  int matched = 0;
  for (auto& p : copy.map_points) {
    if (p && p->bad()) p.reset();  // culled or fused since
    matched += p && p->num_observations() > 0;
  }
  // Fitted again, the frame must keep nearly all the matches it was tracked with
  // (they were all inliers): a velocity that fits it worse is not a better one.
  const int inliers = OptimizePose(copy);
  if (inliers < kMinPoseInliers || inliers < 0.9 * matched) return std::nullopt;
  return copy.T_c_w;
}

bool Tracker::Initialize(Frame& frame, TrackResult& result) {
  const auto& depth = frame.features->depth;
  const auto with_depth = std::count_if(depth.begin(), depth.end(), [](float d) { return d > 0; });
  // At most half the ORB budget (the constructor): not every keypoint has depth, so
  // a frame would never reach the whole budget.
  const int needed = min_init_points_;
  if (with_depth < needed) {
    best_init_depth_points_ = std::max<int>(best_init_depth_points_, static_cast<int>(with_depth));
    if (++init_failures_ == kInitWarnFrames) {
      spdlog::warn(
          "tracking has not started after {} frames: the best had {} keypoints with depth, {} are needed "
          "(500, at most half of orb.features); is the depth image empty, or out of "
          "range for camera.depth_factor?",
          kInitWarnFrames, best_init_depth_points_, needed);
    }
    return false;
  }
  // The map starts from the keypoints that dynamic rejection kept. When it kept
  // few of them (a first frame whose false-positive boxes cover most of the image,
  // with no flow yet to judge by), a map of a hundred points can lose the next
  // frame for good: wait for a frame that keeps at least half of min_init_points_,
  // but not forever (a scene that stays covered by movers must still start).
  // Half, not all: a false "person" box may cover much of the first frame, and the
  // next frame's flow judges those keypoints again (ConfirmStaticInFirstKeyFrame)
  // and brings back the static ones.
  int usable = 0;
  for (std::size_t i = 0; i < depth.size(); ++i) usable += depth[i] > 0 && frame.usable(i);
  if (2 * usable < needed && init_deferred_ < kMaxInitDeferrals) {
    ++init_deferred_;
    return false;
  }
  frame.T_c_w = SE3();  // the first keyframe defines the world frame
  frame.has_pose = true;
  std::unique_lock lock(map_.mutex());
  auto kf = std::make_shared<KeyFrame>(map_.NewKeyFrameId(), frame.id, frame.t, frame.features, frame.T_c_w);
  AddDepthPoints(frame, kf, /*all=*/true);
  TrustAll(kf->map_points());
  map_.AddKeyFrame(kf);
  reference_kf_ = kf;
  frame.reference_kf = kf;
  last_keyframe_frame_id_ = frame.id;
  result.new_keyframe = kf;
  result.reference = kf;
  result.inliers = kf->TrackedMapPoints(1);
  // The first keyframe's keypoints had no velocity to be corrected with: it waits
  // for the next frame too, and gets the angular velocity of the step to it.
  if (KeyFramesWait()) {
    waiting_ = kf;
    before_last_ = Before{frame.id, frame.t, frame.T_c_w, kf, SE3()};
  }
  return true;
}

bool Tracker::TrackWithMotionModel(Frame& frame, TrackResult& result) {
  frame.T_c_w = velocity_ * last_frame_.T_c_w;
  std::fill(frame.map_points.begin(), frame.map_points.end(), nullptr);
  const double r = kMotionSearchRadius;
  int n = matcher::SearchByProjection(frame, last_frame_, r, rejected_match_distance_);
  if (n < kMinMotionMatches) {  // a wider window before giving up
    std::fill(frame.map_points.begin(), frame.map_points.end(), nullptr);
    n = matcher::SearchByProjection(frame, last_frame_, 2 * r, rejected_match_distance_);
  }
  result.matches = n;
  if (n < kMinMotionMatches) return false;
  const int inliers = OptimizePose(frame);
  DiscardOutliers(frame);
  return inliers >= kMinPoseInliers;
}

void Tracker::DiscardOutliers(Frame& frame) {
  for (std::size_t i = 0; i < frame.map_points.size(); ++i) {
    if (frame.outlier[i]) {
      frame.map_points[i].reset();
      frame.outlier[i] = 0;
    }
  }
}

bool Tracker::TrackReferenceKeyFrame(Frame& frame, const std::shared_ptr<KeyFrame>& keyframe, TrackResult& result) {
  if (!keyframe || keyframe->bad()) return false;
  std::fill(frame.map_points.begin(), frame.map_points.end(), nullptr);
  const int n = matcher::SearchByDescriptor(*keyframe, frame, kDescriptorRatio);
  result.matches = n;
  if (n < 15) return false;
  frame.T_c_w = last_frame_.T_c_w;
  const int inliers = OptimizePose(frame);
  DiscardOutliers(frame);
  if (inliers < kMinPoseInliers) return false;
  reference_kf_ = keyframe;
  return true;
}

bool Tracker::TrackOdometry(Frame& frame, TrackResult& result) {
  Frame last = last_frame_;  // its map points, and temporary ones for its other kept keypoints
  const Features& lf = *last.features;
  const SE3 T_w_l = last.T_c_w.Inverse();
  for (std::size_t i = 0; i < last.map_points.size(); ++i) {
    auto& p = last.map_points[i];
    if (p && !p->bad()) continue;
    const auto in_mover = [&] {
      return mover_box_ && std::any_of(lf.detections.begin(), lf.detections.end(), [&](const Detection& d) {
               return d.box.contains(lf.keys[i].pt) && mover_box_(d);
             });
    };
    if (lf.depth[i] <= 0 || lf.depth[i] > th_depth_ || !last.usable(i) || in_mover()) {
      p.reset();
      continue;
    }
    MapPoint::Appearance a;
    const Eigen::Vector3d p_w = T_w_l * lf.Unproject(i);
    a.normal = (p_w - last.center()).normalized();
    std::copy_n(lf.descriptor(i), a.descriptor.size(), a.descriptor.begin());
    const double d = lf.depth[i];
    const double level_factor = lf.scale->scale[static_cast<std::size_t>(lf.keys_un[i].octave)];
    a.max_distance = d * level_factor;
    a.min_distance = a.max_distance / lf.scale->scale.back();
    p = std::make_shared<MapPoint>(kTemporaryPoint, 0, last.t, p_w, a);
    p->track.trusted = true;  // kept by dynamic rejection in the frame before: as trusted as a new map point gets
  }
  frame.T_c_w = (has_velocity_ ? velocity_ : SE3()) * last.T_c_w;
  std::fill(frame.map_points.begin(), frame.map_points.end(), nullptr);
  int n = matcher::SearchByProjection(frame, last, kMotionSearchRadius, rejected_match_distance_);
  if (n < kMinOdometryInliers) {
    std::fill(frame.map_points.begin(), frame.map_points.end(), nullptr);
    n = matcher::SearchByProjection(frame, last, 2 * kMotionSearchRadius, rejected_match_distance_);
  }
  result.matches = n;
  if (n < kMinOdometryInliers) return false;
  OptimizePose(frame);
  DiscardOutliers(frame);
  const int inliers = static_cast<int>(
      std::count_if(frame.map_points.begin(), frame.map_points.end(), [](const auto& p) { return p != nullptr; }));
  result.inliers = inliers;
  return inliers >= kMinOdometryInliers;
}

bool Tracker::RegainMap(Frame& frame, TrackResult& result) {
  // The keyframes of where the camera was lost first: most losses are short (movers
  // cover the view for a moment) and end where they began. Place recognition alone
  // asks for 50 inliers from one keyframe and left lost frames that the local
  // candidates place, at a cost in accuracy (docs/tracking-states.md, "Back into the map").
  return Recover(frame, result) || (places_ && Relocalise(frame, result));
}

bool Tracker::Recover(Frame& frame, TrackResult& result) {
  // The most recent keyframes (they see what the camera saw when it was lost, even
  // if its last poses drifted), then those nearest to the last good pose, up to
  // kRecoverCandidates (in a room-sized map that is every keyframe: the camera may
  // come back to any view; a larger map is searched by place recognition). Each is matched
  // by descriptor, and the pose comes from PnP RANSAC on the matches, not from the
  // last pose: after a failure that pose is the least trustworthy (ORB-SLAM2's
  // relocalisation does the same with BoW candidates).
  std::vector<std::shared_ptr<KeyFrame>> candidates;
  const auto& all = map_.keyframes();
  for (auto it = all.rbegin(); it != all.rend() && candidates.size() < 5; ++it) {
    if (!it->second->bad()) candidates.push_back(it->second);
  }
  const Eigen::Vector3d last_center = last_frame_.center();
  std::vector<std::pair<double, std::shared_ptr<KeyFrame>>> near;
  for (const auto& [id, kf] : all) {
    if (!kf->bad()) near.emplace_back((kf->center() - last_center).norm(), kf);
  }
  std::stable_sort(near.begin(), near.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  const auto cap = static_cast<std::size_t>(kRecoverCandidates);
  if (candidates.size() > cap) candidates.resize(cap);
  for (const auto& [d, kf] : near) {
    if (candidates.size() >= cap) break;
    if (std::find(candidates.begin(), candidates.end(), kf) == candidates.end()) candidates.push_back(kf);
  }
  for (const auto& kf : candidates) {
    std::fill(frame.map_points.begin(), frame.map_points.end(), nullptr);
    const int n = matcher::SearchByDescriptor(*kf, frame, kDescriptorRatio);
    result.matches = n;
    if (n < 15) continue;
    const std::optional<SE3> T_c_w = PnpOnMatches(frame, {300, 4.0, kMinPoseInliers});
    if (!T_c_w) continue;
    frame.T_c_w = *T_c_w;
    const int inliers = OptimizePose(frame);
    DiscardOutliers(frame);
    if (inliers < kMinPoseInliers) continue;
    reference_kf_ = kf;
    return true;
  }
  return false;
}

namespace {
// ORB-SLAM2's relocalisation thresholds.
constexpr int kRelocMinBowMatches = 15;
constexpr double kRelocBowRatio = 0.75;
constexpr int kRelocPnpMinInliers = 10;
constexpr int kRelocGoodInliers = 50;
constexpr int kRelocCandidates = 20;  // tried per frame, best pools first (bounds a lost frame's time)
}  // namespace

bool Tracker::Relocalise(Frame& frame, TrackResult& result) {
  const auto bow = places_->Describe(frame.features->descriptors);
  const std::vector<PlaceCandidate> candidates = places_->RelocalisationCandidates(bow->words);
  int tried = 0;
  for (const PlaceCandidate& c : candidates) {
    if (c.keyframe->bad()) continue;
    if (++tried > kRelocCandidates) break;
    if (!RelocaliseWith(frame, *c.keyframe, *bow)) continue;
    reference_kf_ = c.keyframe;
    result.matches = static_cast<int>(std::count_if(frame.map_points.begin(), frame.map_points.end(),
                                                    [](const auto& p) { return p != nullptr; }));
    spdlog::debug("frame {}: relocalised on keyframe {} ({} candidates)", frame.id, c.keyframe->id, candidates.size());
    return true;
  }
  return false;
}

bool Tracker::RelocaliseWith(Frame& frame, const KeyFrame& candidate, const vocab::BowData& bow) {
  std::fill(frame.map_points.begin(), frame.map_points.end(), nullptr);
  if (matcher::SearchByBow(candidate, frame, bow.nodes, kRelocBowRatio) < kRelocMinBowMatches) return false;
  const std::optional<SE3> T_c_w = PnpOnMatches(frame, {300, 2.5, kRelocPnpMinInliers});
  if (!T_c_w) return false;
  frame.T_c_w = *T_c_w;
  int inliers = OptimizePose(frame);
  DiscardOutliers(frame);
  if (inliers < kRelocPnpMinInliers) return false;
  // Too few: more of the candidate's points by projection, wide then narrow.
  if (inliers < kRelocGoodInliers &&
      inliers + matcher::SearchByProjection(frame, candidate, 10, 100) >= kRelocGoodInliers) {
    inliers = OptimizePose(frame);
    if (inliers > 30 && inliers < kRelocGoodInliers &&
        inliers + matcher::SearchByProjection(frame, candidate, 3, 64) >= kRelocGoodInliers) {
      inliers = OptimizePose(frame);
    }
    DiscardOutliers(frame);
  }
  return inliers >= kRelocGoodInliers;
}

bool Tracker::TrackLocalMap(Frame& frame, TrackResult& result) {
  if (auto ref = local_map_.Update(frame)) reference_kf_ = ref;
  local_map_.Search(frame, kLocalSearchRadius, rejected_match_distance_);
  result.matches = static_cast<int>(std::count_if(frame.map_points.begin(), frame.map_points.end(),
                                                  [](const auto& p) { return p != nullptr; }));
  OptimizePose(frame);
  RefineRollingShutter(frame);
  UpdateTrust(frame, trust_);
  result.trusted = CountTrustedInliers(frame);
  int inliers = 0;
  for (std::size_t i = 0; i < frame.map_points.size(); ++i) {
    const auto& p = frame.map_points[i];
    if (!p || frame.outlier[i]) continue;
    p->IncreaseFound();
    if (p->num_observations() > 0) ++inliers;
  }
  result.inliers = inliers;
  return inliers >= kMinLocalInliers;
}

void Tracker::RefineRollingShutter(Frame& frame) {
  const std::shared_ptr<const Features> held = frame.features;  // f stays valid when replaced below
  const Features& f = *held;
  const double readout = f.camera->config().readout;
  if (readout <= 0 || !config_.refinements.rolling_shutter_refine) return;
  std::vector<optim::PoseObservation> obs;
  std::vector<double> row_time;
  for (std::size_t i = 0; i < frame.map_points.size(); ++i) {
    if (!frame.map_points[i] || frame.outlier[i]) continue;
    obs.push_back(PoseObservationOf(f, i, *frame.map_points[i]));
    row_time.push_back(RowTimeOffset(f.keys[i].pt.y, f.camera->height(), readout));
  }
  optim::RollingShutterPoseOptions options;
  options.prior_sigma = kRollingShutterPrior;
  const auto r = optim::OptimizePoseAndAngularVelocity(frame.T_c_w, obs, row_time, IntrinsicsOf(*f.camera), options);
  if (!r.ok) return;
  frame.features = WithRollingShutterCorrection(f, f.angular_velocity + r.delta);
  frame.T_c_w = r.T_c_w;
  OptimizePose(frame);  // classifies the matches again at the corrected keypoints
}

int Tracker::OptimizePose(Frame& frame) {
  const Features& f = *frame.features;
  std::vector<optim::PoseObservation> obs;
  std::vector<std::size_t> index;
  std::vector<bool> trusted;
  for (std::size_t i = 0; i < frame.map_points.size(); ++i) {
    const auto& p = frame.map_points[i];
    if (!p) continue;
    trusted.push_back(p->track.trusted);
    obs.push_back(PoseObservationOf(f, i, *p));
    index.push_back(i);
  }
  std::fill(frame.outlier.begin(), frame.outlier.end(), 0);
  if (obs.size() < 3) return 0;
  const auto r = OptimizePoseTrusted(frame.T_c_w, std::move(obs), trusted, IntrinsicsOf(*f.camera), trust_);
  frame.T_c_w = r.T_c_w;
  int inliers = 0;
  for (std::size_t k = 0; k < index.size(); ++k) {
    if (r.inlier[k]) {
      if (frame.map_points[index[k]]->num_observations() > 0) ++inliers;
    } else {
      frame.outlier[index[k]] = 1;
    }
  }
  return inliers;
}

}  // namespace sgslam
