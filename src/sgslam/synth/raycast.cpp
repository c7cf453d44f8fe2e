#include "sgslam/synth/raycast.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

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

// The hits of quad qi (camera frame) on row y, pixels x0..x1-1, kept where nearer.
void CastRow(const Quad& q, int qi, int y, int x0, int x1, const std::vector<double>& ray_x, const Intrinsics& K,
             RayCastResult& out) {
  const Eigen::Vector3d n = q.normal();
  const double nc = n.dot(q.centre);  // plane: n . p = nc; the camera sits at p = 0
  const double ry = (y - K.cy) / K.fy;
  const double ny = n.y() * ry + n.z();
  double* depth = out.depth.data() + static_cast<std::size_t>(y) * K.width;
  int* surface = out.surface.ptr<int>(y);
  for (int x = x0; x < x1; ++x) {
    const double z = nc / (n.x() * ray_x[x] + ny);  // ray p = z * (rx, ry, 1)
    if (!(z > kNear && z < depth[x])) continue;
    const Eigen::Vector3d d(z * ray_x[x] - q.centre.x(), z * ry - q.centre.y(), z - q.centre.z());
    if (std::abs(q.axis_u.dot(d)) > q.half_u || std::abs(q.axis_v.dot(d)) > q.half_v) continue;
    depth[x] = z;
    surface[x] = qi;
  }
}

// Whether the quad can be seen at all: not from behind, not edge-on.
bool Facing(const Quad& q) {
  const double nc = q.normal().dot(q.centre);
  if (!q.two_sided && nc >= 0) return false;  // camera behind the visible side
  return std::abs(nc) >= 1e-12;               // plane through the camera: seen edge-on
}

RayCastResult EmptyResult(const Intrinsics& K, std::vector<double>& ray_x) {
  RayCastResult out;
  out.depth.assign(static_cast<std::size_t>(K.width) * K.height, std::numeric_limits<double>::infinity());
  out.surface = cv::Mat(K.height, K.width, CV_32S, cv::Scalar(-1));
  ray_x.resize(K.width);
  for (int x = 0; x < K.width; ++x) ray_x[x] = (x - K.cx) / K.fx;
  return out;
}

}  // namespace

RayCastResult RayCast(const std::vector<Quad>& quads_c, const Intrinsics& K) {
  std::vector<double> ray_x;
  RayCastResult out = EmptyResult(K, ray_x);
  for (int qi = 0; qi < static_cast<int>(quads_c.size()); ++qi) {
    const Quad& q = quads_c[qi];
    if (!Facing(q)) continue;
    const Rect r = ScreenRect(q, K);
    for (int y = r.y0; y < r.y1; ++y) CastRow(q, qi, y, r.x0, r.x1, ray_x, K, out);
  }
  return out;
}

RayCastResult RayCastRows(const std::vector<Quad>& quads_w, const std::vector<SE3>& T_c_w_rows, const Intrinsics& K) {
  if (T_c_w_rows.size() != static_cast<std::size_t>(K.height)) {
    throw std::invalid_argument("RayCastRows: one camera pose per image row is needed");
  }
  std::vector<double> ray_x;
  RayCastResult out = EmptyResult(K, ray_x);
  for (int y = 0; y < K.height; ++y) {
    for (int qi = 0; qi < static_cast<int>(quads_w.size()); ++qi) {
      const Quad q = Transformed(T_c_w_rows[static_cast<std::size_t>(y)], quads_w[qi]);
      if (!Facing(q)) continue;
      const Rect r = ScreenRect(q, K);
      if (y >= r.y0 && y < r.y1) CastRow(q, qi, y, r.x0, r.x1, ray_x, K, out);
    }
  }
  return out;
}

}  // namespace sgslam::synth
