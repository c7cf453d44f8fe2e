// Loop closing (ORB-SLAM2's LoopClosing, for RGB-D: SE(3), depth fixes the scale).
//
// Detect(), for every keyframe local mapping finished: loop candidates from the
// place-recognition database (keyframes that are not its neighbours and score at
// least as well as its worst covisible neighbour), kept only when consistent over
// three consecutive keyframes (a candidate's covisibility group overlaps a group
// of the previous keyframe's); then geometric verification: bag-of-words matches
// between the keyframe's map points and the candidate's, an SE(3) RANSAC on them
// (geometry/rigid.h), a pose fit of the keyframe to the candidate's points, the
// points of the candidate's neighbourhood projected for more matches, and a last
// fit that must keep kMinLoopInliers; and the correction must be one drift could
// have made: at most kMaxDriftBase + kMaxDriftRatio times the path the keyframes
// travelled between the two (and as much in rotation, per metre), or it is a place
// that only looks the same (a repeated corridor). A loop that fails is counted,
// never applied.
//
// Correct(): the keyframe and its covisible neighbours move rigidly to the pose
// the loop says, with the points they see; duplicated points are fused across the
// loop; the essential graph (spanning tree, loop edges, strong covisibility) is
// optimised with the loop's new links as constraints (optim/pose_graph.h); every
// keyframe takes its optimised pose and every point follows its reference
// keyframe. Keyframes tracking made that local mapping has not inserted yet move
// with the current keyframe.
//
// Threading: Detect() runs on the loop thread and reads under Map::mutex()
// shared. Correct() takes the lock exclusively; the caller must have paused local
// mapping (no local BA may write back poses from before the correction).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <set>
#include <utility>
#include <vector>

#include "sgslam/loop/keyframe_database.h"
#include "sgslam/map/map.h"

namespace sgslam {

struct VerifiedLoop {
  std::shared_ptr<KeyFrame> current;  // the new keyframe
  std::shared_ptr<KeyFrame> loop;     // the old keyframe it sees again
  SE3 T_c_w;                          // current's pose in the loop side's frame of reference, at Detect
  SE3 T_cur_loop;                     // current relative to the loop keyframe (Correct starts from it:
                                      // a global BA may move the loop side between Detect and Correct)
  // One per current keypoint: the loop side's map point matched to it, or null.
  std::vector<std::shared_ptr<MapPoint>> matched;
  // The points of the loop keyframe and its covisible neighbours.
  std::vector<std::shared_ptr<MapPoint>> loop_points;
  int inliers = 0;
};

// What the loop closer did with one keyframe.
struct LoopReport {
  std::uint64_t keyframe = 0;
  int candidates = 0;  // from the database
  int consistent = 0;  // consistent over kConsistency keyframes
  int rejected = 0;    // consistent candidates that failed geometric verification
  int implausible = 0; // ... that passed it with a correction drift could not explain
  bool closed = false;
  std::uint64_t loop_keyframe = 0;
  std::uint64_t frame = 0, loop_frame = 0;  // the frames the two keyframes were made from
  Timestamp t = 0, loop_t = 0;
  int inliers = 0;             // of the accepted loop's last fit
  double correction_m = 0;     // how far the current keyframe moved
  double correction_deg = 0;   // ... and turned
  int corrected_keyframes = 0; // in the pose graph
  int fused = 0;               // points merged across the loop
  double detect_ms = 0, correct_ms = 0, pose_graph_ms = 0;
};

class LoopCloser {
 public:
  LoopCloser(Map& map, std::shared_ptr<const KeyFrameDatabase> places) : map_(map), places_(std::move(places)) {}

  std::optional<VerifiedLoop> Detect(const std::shared_ptr<KeyFrame>& kf, LoopReport& report);
  void Correct(const VerifiedLoop& loop, LoopReport& report);

  static constexpr int kConsistency = 3;       // consecutive keyframes a candidate must hold over
  static constexpr int kMinBowMatches = 20;    // SE(3) RANSAC's minimum inliers too
  static constexpr int kMinLoopInliers = 40;   // after the neighbourhood's points were added
  static constexpr std::uint64_t kMinKeyFrames = 10;  // in the map, and since the last loop
  static constexpr double kMaxDriftBase = 0.3;         // m
  static constexpr double kMaxDriftRatio = 0.1;        // m of drift per m travelled
  static constexpr double kMaxTurnBase = 5;            // deg
  static constexpr double kMaxTurnPerMetre = 1;        // deg per m travelled

 private:
  using Group = std::pair<std::set<std::uint64_t>, int>;  // covisibility group, consistency
  std::vector<std::shared_ptr<KeyFrame>> ConsistentCandidates(const std::vector<PlaceCandidate>& candidates);
  std::optional<VerifiedLoop> Verify(const std::shared_ptr<KeyFrame>& kf, const std::shared_ptr<KeyFrame>& candidate);
  // Whether drift along the keyframes between the two could have made the correction.
  bool Plausible(const VerifiedLoop& loop) const;
  // Fits kf's pose T_c_w to the matched points; drops the outliers from matched.
  static int FitPose(const KeyFrame& kf, std::vector<std::shared_ptr<MapPoint>>& matched, SE3& T_c_w);
  void FuseLoopPoints(const VerifiedLoop& loop, const std::vector<std::shared_ptr<KeyFrame>>& connected,
                      LoopReport& report);
  // Fuses the loop's points and returns the links it made: per keyframe of the
  // current's neighbourhood, the keyframes outside it it is newly connected to.
  std::map<std::uint64_t, std::set<std::uint64_t>> FuseAndLink(const VerifiedLoop& loop,
                                                               const std::vector<std::shared_ptr<KeyFrame>>& connected,
                                                               LoopReport& report);
  // moved_by: the keyframe whose rigid correction moved each point (Correct's first step).
  void OptimizeEssentialGraph(const VerifiedLoop& loop, const std::map<std::uint64_t, SE3>& before,
                              const std::map<std::uint64_t, std::set<std::uint64_t>>& new_links,
                              const std::vector<std::shared_ptr<KeyFrame>>& pending,
                              const std::map<std::uint64_t, std::uint64_t>& moved_by, LoopReport& report);

  Map& map_;
  const std::shared_ptr<const KeyFrameDatabase> places_;
  std::vector<Group> groups_;  // of the previous keyframe's candidates
  std::uint64_t last_loop_kf_ = 0;
  int loops_closed_ = 0;
};

}  // namespace sgslam
