// The keyframe decision and keyframe creation of the tracker (ORB-SLAM2's
// NeedNewKeyFrame / CreateNewKeyFrame for RGB-D).
#include <algorithm>
#include <cstdint>
#include <mutex>
#include <shared_mutex>

#include "sgslam/tracking/tracker.h"
#include "sgslam/tracking/trusted_pose.h"

namespace sgslam {

namespace {

// ORB-SLAM2's keyframe rules for RGB-D.
constexpr double kKeyFrameRefRatio = 0.75;       // a keyframe when tracked points fall below this share of the reference's
constexpr int kMaxFramesBetweenKeyFrames = 30;   // frames at most between keyframes
constexpr int kCloseTrackedMin = 100;            // a keyframe is needed when fewer close points are tracked ...
constexpr int kCloseUntrackedMin = 70;           // ... and more than this many close points are not
constexpr int kKeyFrameMinNewPoints = 100;       // points created per keyframe beyond the close range

}  // namespace

bool Tracker::NeedNewKeyFrame(const Frame& frame, int inliers, bool mapping_idle, bool mapping_full) const {
  if (mapping_full) return false;
  const std::size_t keyframes = map_.keyframes().size();
  const int min_obs = keyframes <= 2 ? 2 : 3;
  const int ref_tracked = reference_kf_ ? reference_kf_->TrackedMapPoints(min_obs) : 0;

  // Close points (reliable depth) tracked and not tracked: a view of much new
  // close structure needs a keyframe even when the tracked ratio is still high,
  // which keeps tracking alive through fast rotations.
  int close_tracked = 0, close_untracked = 0;
  const auto& depth = frame.features->depth;
  for (std::size_t i = 0; i < depth.size(); ++i) {
    if (depth[i] <= 0 || depth[i] >= th_depth_ || frame.rejected[i]) continue;
    if (frame.map_points[i] && !frame.outlier[i]) ++close_tracked;
    else ++close_untracked;
  }
  const bool need_close = close_tracked < kCloseTrackedMin &&
                          close_untracked > kCloseUntrackedMin;
  const double ratio = keyframes < 2 ? 0.4 : kKeyFrameRefRatio;
  const auto max_gap = static_cast<std::uint64_t>(kMaxFramesBetweenKeyFrames);
  const std::uint64_t since = frame.id - last_keyframe_frame_id_;
  const bool c1a = since >= max_gap;
  const bool c1b = mapping_idle;
  const bool c1c = inliers < ref_tracked * 0.25 || need_close;
  const bool c2 = (inliers < ref_tracked * ratio || need_close) && inliers > 15;
  return (c1a || c1b || c1c) && c2;
}

std::shared_ptr<KeyFrame> Tracker::CreateKeyFrame(Frame& frame, const SE3& T_c_r, std::uint64_t corrections) {
  std::unique_lock lock(map_.mutex());
  if (map_.corrections() != corrections) frame.T_c_w = T_c_r * reference_kf_->T_c_w();  // a loop was closed since
  auto kf = std::make_shared<KeyFrame>(map_.NewKeyFrameId(), frame.id, frame.t, frame.features, frame.T_c_w);
  // Matched points join the keyframe now; local mapping adds the observations.
  for (std::size_t i = 0; i < frame.map_points.size(); ++i) {
    const auto& p = frame.map_points[i];
    if (p && !frame.outlier[i] && !p->bad()) kf->SetMapPoint(i, p);
  }
  AddDepthPoints(frame, kf, /*all=*/false);
  map_.AddPending(kf);  // until local mapping inserts it
  reference_kf_ = kf;
  frame.reference_kf = kf;
  last_keyframe_frame_id_ = frame.id;
  return kf;
}

int Tracker::AddDepthPoints(Frame& frame, const std::shared_ptr<KeyFrame>& kf, bool all) {
  const Features& f = *frame.features;
  std::vector<std::pair<float, std::size_t>> by_depth;
  for (std::size_t i = 0; i < f.size(); ++i) {
    // A keypoint matched to a map point but an outlier of the pose optimisation
    // disagrees with the map: on a moving object it would re-enter the map at
    // every keyframe at its new place. Only with dynamic rejection on (labels
    // present): mode none stays ORB-SLAM2's rule.
    // No new point from a keypoint that was a pose outlier in a dynamic mode: it
    // may be a mover the rejection missed.
    const bool suspect = frame.map_points[i] && frame.outlier[i] && !f.dynamic.empty();
    if (f.depth[i] > 0 && !frame.rejected[i] && !suspect) {
      by_depth.emplace_back(f.depth[i], i);
    }
  }
  std::sort(by_depth.begin(), by_depth.end());
  const SE3 T_w_c = frame.T_c_w.Inverse();
  int created = 0, visited = 0;
  for (const auto& [d, i] : by_depth) {
    // All close points, and at least keyframe_min_new_points in total (ORB-SLAM2).
    if (!all && d > th_depth_ && visited > kKeyFrameMinNewPoints) break;
    ++visited;
    const auto& existing = kf->map_point(i);
    if (existing && existing->num_observations() > 0) continue;
    auto p = std::make_shared<MapPoint>(map_.NewMapPointId(), T_w_c * f.Unproject(i), kf);
    p->AddObservation(kf, i);
    kf->SetMapPoint(i, p);
    p->UpdateDescriptor();
    p->UpdateNormalAndDepth();
    map_.AddMapPoint(p);
    frame.map_points[i] = p;
    frame.outlier[i] = 0;
    ++created;
  }
  return created;
}

int Tracker::ConfirmStaticInFirstKeyFrame(const std::vector<std::uint8_t>& now_static) {
  // A loaded map's keyframe may carry the frame id of this run's first frame.
  if (localization_only_ || state_ != TrackState::kOk || !reference_kf_ || !last_frame_.features) return 0;
  const std::shared_ptr<KeyFrame> kf = reference_kf_;
  std::unique_lock lock(map_.mutex());  // the keyframe list, then the keyframe's features and points
  if (map_.keyframes().size() != 1 || kf->frame_id != last_frame_.id) return 0;
  const Features& f = *kf->features;
  if (f.dynamic.size() != f.size() || now_static.size() != f.size()) return 0;
  std::vector<std::uint8_t> dynamic = f.dynamic;
  int cleared = 0;
  for (std::size_t i = 0; i < f.size(); ++i) {
    if (dynamic[i] && now_static[i] && f.depth[i] > 0) dynamic[i] = 0, ++cleared;
  }
  if (cleared == 0) return 0;
  auto relabelled = std::make_shared<Features>(f);
  relabelled->dynamic = std::move(dynamic);
  kf->ReplaceFeatures(relabelled);
  last_frame_.features = relabelled;
  last_frame_.rejected = relabelled->dynamic;
  AddDepthPoints(last_frame_, kf, /*all=*/true);
  // Trusted like the first keyframe's other points (trusted_pose.h), which only had
  // to lie outside the boxes: these passed Algorithm 1 and the RGB-D check.
  TrustAll(kf->map_points());
  return cleared;
}

}  // namespace sgslam
