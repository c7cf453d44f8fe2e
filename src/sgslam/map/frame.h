// A frame being tracked: its features, the map points its keypoints were matched
// to, and its pose. Owned by the tracking thread; never shared with other threads
// except through the keyframe made from it.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <opencv2/core.hpp>

#include "sgslam/common/se3.h"
#include "sgslam/common/time.h"
#include "sgslam/map/features.h"

namespace sgslam {

class KeyFrame;
class MapPoint;

struct Frame {
  std::uint64_t id = 0;
  Timestamp t = 0;
  std::shared_ptr<const Features> features;
  std::vector<std::shared_ptr<MapPoint>> map_points;  // by keypoint; nullptr where none
  std::vector<std::uint8_t> outlier;                  // set by pose optimisation
  std::vector<std::uint8_t> rejected;                 // dynamic: never mapped; matched only as matcher.h says
  SE3 T_c_w;
  bool has_pose = false;
  // Judged by its detection boxes alone (sg's first frame, no flow yet): the next
  // frame judges its keypoints again (DynamicOutcome::judged_again).
  bool judged_again = false;
  std::shared_ptr<KeyFrame> reference_kf;

  Frame() = default;
  Frame(std::uint64_t frame_id, Timestamp stamp, std::shared_ptr<const Features> feats);

  std::size_t size() const { return features->size(); }
  Eigen::Vector3d center() const { return T_c_w.Inverse().translation(); }
  bool usable(std::size_t i) const { return !rejected[i]; }

  // Whether a map point projects into this frame at a scale and viewing angle from
  // which it can be matched; fills point.track (tracking thread) with the
  // prediction. Reads the point's [map] fields: hold the map's shared lock.
  bool IsInFrustum(MapPoint& point, double viewing_cos_limit) const;
};

}  // namespace sgslam
