#include "sgslam/map/frame.h"

#include "sgslam/map/map_point.h"

namespace sgslam {

Frame::Frame(std::uint64_t frame_id, Timestamp stamp, std::shared_ptr<const Features> feats)
    : id(frame_id),
      t(stamp),
      features(std::move(feats)),
      map_points(features->size()),
      outlier(features->size(), 0),
      rejected(features->dynamic.empty() ? std::vector<std::uint8_t>(features->size(), 0) : features->dynamic) {}

bool Frame::IsInFrustum(MapPoint& point, double viewing_cos_limit) const {
  point.track.in_view = false;
  const Eigen::Vector3d& p_w = point.position();
  const Eigen::Vector3d p_c = T_c_w * p_w;
  if (p_c.z() <= 0) return false;
  const Camera& cam = *features->camera;
  const Eigen::Vector2d uv = cam.Project(p_c);
  if (!features->bounds.Contains(uv.x(), uv.y())) return false;
  // Within the distance range the point's descriptor is valid for.
  const Eigen::Vector3d ray = p_w - center();
  const double distance = ray.norm();
  if (distance < point.min_distance() || distance > point.max_distance()) return false;
  const double view_cos = ray.dot(point.normal()) / distance;
  if (view_cos < viewing_cos_limit) return false;
  point.track.in_view = true;
  point.track.u = uv.x();
  point.track.v = uv.y();
  point.track.u_right = uv.x() - cam.baseline_fx() / p_c.z();
  point.track.view_cos = view_cos;
  point.track.predicted_level = point.PredictScale(distance, *features->scale);
  return true;
}

}  // namespace sgslam
