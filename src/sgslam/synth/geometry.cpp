#include "sgslam/synth/geometry.h"

#include <cmath>
#include <limits>

namespace sgslam::synth {

void Quad::Corners(Eigen::Vector3d corners[4]) const {
  const Eigen::Vector3d u = half_u * axis_u, v = half_v * axis_v;
  corners[0] = centre - u - v;
  corners[1] = centre + u - v;
  corners[2] = centre + u + v;
  corners[3] = centre - u + v;
}

Quad MakeQuad(const Eigen::Vector3d& centre, const Eigen::Vector3d& u, const Eigen::Vector3d& v, double hu, double hv,
              int texture) {
  Quad q;
  q.centre = centre;
  q.axis_u = u;
  q.axis_v = v;
  q.half_u = hu;
  q.half_v = hv;
  q.texture = texture;
  return q;
}

Quad Transformed(const SE3& T_b_a, const Quad& quad) {
  Quad out = quad;
  out.centre = T_b_a * quad.centre;
  out.axis_u = T_b_a.quaternion() * quad.axis_u;
  out.axis_v = T_b_a.quaternion() * quad.axis_v;
  return out;
}

void AddBox(std::vector<Quad>& quads, const Eigen::Vector3d& centre, const Eigen::Vector3d& size, double yaw,
            int object, int texture) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d h = 0.5 * size;
  for (int axis = 0; axis < 3; ++axis) {
    const int a = (axis + 1) % 3, b = (axis + 2) % 3;  // a x b = +axis
    for (int sign = -1; sign <= 1; sign += 2) {
      Quad q;
      q.centre = centre + R.col(axis) * (sign * h[axis]);
      q.axis_u = R.col(sign > 0 ? a : b);  // swap for the negative face so the normal points out
      q.axis_v = R.col(sign > 0 ? b : a);
      q.half_u = sign > 0 ? h[a] : h[b];
      q.half_v = sign > 0 ? h[b] : h[a];
      q.object = object;
      q.texture = texture;
      const int face = 2 * axis + (sign > 0);
      q.texture_offset = Eigen::Vector2d(1.37 * face, 0.71 * face);
      quads.push_back(q);
    }
  }
}

void Bounds(const std::vector<Quad>& quads, Eigen::Vector3d& min, Eigen::Vector3d& max) {
  min.setConstant(std::numeric_limits<double>::infinity());
  max = -min;
  Eigen::Vector3d corners[4];
  for (const Quad& q : quads) {
    q.Corners(corners);
    for (const auto& c : corners) {
      min = min.cwiseMin(c);
      max = max.cwiseMax(c);
    }
  }
}

double IntersectRay(const Quad& quad, const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) {
  const Eigen::Vector3d n = quad.normal();
  const double denom = n.dot(direction);
  if (std::abs(denom) < 1e-15) return -1;
  if (!quad.two_sided && n.dot(origin - quad.centre) <= 0) return -1;  // behind the visible side
  const double t = n.dot(quad.centre - origin) / denom;
  if (t <= 0) return -1;
  return quad.Contains(origin + t * direction) ? t : -1;
}

}  // namespace sgslam::synth
