#include "sgslam/synth/raycast.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sgslam::synth {

namespace {

constexpr double kNear = 1e-6;  // m, hits closer than this are ignored

struct Rect {
  int x0, y0, x1, y1;  // inclusive-exclusive
};

// Pixels the quad's projection can cover; empty when it is wholly behind the camera.
Rect ScreenRect(const Quad& q, const Intrinsics& K) {
  Eigen::Vector3d corners[4];
  q.Corners(corners);
  int behind = 0;
  double u0 = 1e300, u1 = -1e300, v0 = 1e300, v1 = -1e300;
  for (const auto& c : corners) {
    if (c.z() <= kNear) {
      ++behind;
      continue;
    }
    const double u = K.fx * c.x() / c.z() + K.cx, v = K.fy * c.y() / c.z() + K.cy;
    u0 = std::min(u0, u), u1 = std::max(u1, u), v0 = std::min(v0, v), v1 = std::max(v1, v);
  }
  if (behind == 4) return {0, 0, 0, 0};
  if (behind > 0) return {0, 0, K.width, K.height};
  // The projection of a quad in front of the camera is the hull of its corners'.
  const auto clamp = [](double x, int hi) { return static_cast<int>(std::clamp(x, 0.0, static_cast<double>(hi))); };
  return {clamp(std::floor(u0) - 1, K.width), clamp(std::floor(v0) - 1, K.height), clamp(std::ceil(u1) + 2, K.width),
          clamp(std::ceil(v1) + 2, K.height)};
}

}  // namespace

RayCastResult RayCast(const std::vector<Quad>& quads_c, const Intrinsics& K) {
  RayCastResult out;
  out.depth.assign(static_cast<std::size_t>(K.width) * K.height, std::numeric_limits<double>::infinity());
  out.surface = cv::Mat(K.height, K.width, CV_32S, cv::Scalar(-1));
  std::vector<double> ray_x(K.width);
  for (int x = 0; x < K.width; ++x) ray_x[x] = (x - K.cx) / K.fx;

  for (int qi = 0; qi < static_cast<int>(quads_c.size()); ++qi) {
    const Quad& q = quads_c[qi];
    const Eigen::Vector3d n = q.normal();
    const double nc = n.dot(q.centre);  // plane: n . p = nc; the camera sits at p = 0
    if (!q.two_sided && nc >= 0) continue;  // camera behind the visible side
    if (std::abs(nc) < 1e-12) continue;     // plane through the camera: seen edge-on
    const Rect r = ScreenRect(q, K);
    for (int y = r.y0; y < r.y1; ++y) {
      const double ry = (y - K.cy) / K.fy;
      const double ny = n.y() * ry + n.z();
      double* depth = out.depth.data() + static_cast<std::size_t>(y) * K.width;
      int* surface = out.surface.ptr<int>(y);
      for (int x = r.x0; x < r.x1; ++x) {
        const double z = nc / (n.x() * ray_x[x] + ny);  // ray p = z * (rx, ry, 1)
        if (!(z > kNear && z < depth[x])) continue;
        const Eigen::Vector3d d(z * ray_x[x] - q.centre.x(), z * ry - q.centre.y(), z - q.centre.z());
        if (std::abs(q.axis_u.dot(d)) > q.half_u || std::abs(q.axis_v.dot(d)) > q.half_v) continue;
        depth[x] = z;
        surface[x] = qi;
      }
    }
  }
  return out;
}

}  // namespace sgslam::synth
