#include "sgslam/camera/rolling_shutter.h"

#include "sgslam/camera/camera.h"

namespace sgslam {

std::optional<Eigen::Vector3d> AngularVelocity(const SE3& T_cur_last, double dt) {
  if (!(dt > 0)) return std::nullopt;
  // R_cur_last = R_w_c(cur)^T R_w_c(last) = Exp(-w dt).
  return -so3::Log(T_cur_last.quaternion()) / dt;
}

void CorrectRollingShutter(const Camera& camera, const std::vector<cv::KeyPoint>& raw, const Eigen::Vector3d& from,
                           const Eigen::Vector3d& to, std::vector<cv::KeyPoint>& undistorted,
                           std::vector<float>& depth) {
  const double readout = camera.config().readout;
  if (readout <= 0 || from == to) return;
  for (std::size_t i = 0; i < undistorted.size(); ++i) {
    const double s = RowTimeOffset(raw[i].pt.y, camera.height(), readout);
    // Exp(to s) Exp(-from s): undo the earlier correction, apply the new one.
    const Eigen::Quaterniond q = so3::Exp(to * s) * so3::Exp(-from * s);
    const bool has_depth = depth[i] > 0;
    const Eigen::Vector3d p = q * camera.Unproject(undistorted[i].pt.x, undistorted[i].pt.y, has_depth ? depth[i] : 1.0);
    if (p.z() <= 0) continue;  // cannot happen for rotations of a few degrees
    const Eigen::Vector2d uv = camera.Project(p);
    undistorted[i].pt = cv::Point2f(static_cast<float>(uv.x()), static_cast<float>(uv.y()));
    if (has_depth) depth[i] = static_cast<float>(p.z());
  }
}

}  // namespace sgslam
