// Where a map point should be searched for in an image (the first step of every
// projection search: fusion, loop closing, relocalisation's guided search). Internal
// to matching/.
#pragma once

#include <optional>

#include <Eigen/Core>

#include "sgslam/common/se3.h"
#include "sgslam/map/features.h"
#include "sgslam/map/map_point.h"

namespace sgslam::matcher {

struct SearchWindow {
  Eigen::Vector2d uv;  // px, the projection
  double depth = 0;    // m, in the camera
  int level = 0;       // predicted pyramid level
  double radius = 0;   // px, th * the level's scale
};

// p seen by a camera at T_c_w (centre: its position): in front of it, inside f's
// bounds, within the point's scale-invariance distances and, with view_check, seen
// at most 60 degrees off its mean viewing direction (ORB-SLAM2's tests); none when
// a test fails.
inline std::optional<SearchWindow> ProjectForSearch(const MapPoint& p, const SE3& T_c_w, const Eigen::Vector3d& centre,
                                                    const Features& f, double th, bool view_check) {
  const Eigen::Vector3d p_w = p.position();
  const Eigen::Vector3d p_c = T_c_w * p_w;
  if (p_c.z() <= 0) return std::nullopt;
  const Eigen::Vector2d uv = f.camera->Project(p_c);
  if (!f.bounds.Contains(uv.x(), uv.y())) return std::nullopt;
  const double distance = (p_w - centre).norm();
  if (distance < p.min_distance() || distance > p.max_distance()) return std::nullopt;
  if (view_check && (p_w - centre).dot(p.normal()) < 0.5 * distance) return std::nullopt;
  const int level = p.PredictScale(distance, *f.scale);
  return SearchWindow{uv, p_c.z(), level, th * f.scale->scale[static_cast<std::size_t>(level)]};
}

}  // namespace sgslam::matcher
