#include "sgslam/synth/room.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace sgslam::synth {

namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

Quad MakeQuad(const Vector3d& centre, const Vector3d& u, const Vector3d& v, double hu, double hv, int texture) {
  Quad q;
  q.centre = centre;
  q.axis_u = u;
  q.axis_v = v;
  q.half_u = hu;
  q.half_v = hv;
  q.texture = texture;
  return q;
}

double SegmentDistance(const Vector2d& p, const KeepOut& k) {
  const Vector2d ab = k.b - k.a;
  const double len2 = ab.squaredNorm();
  const double s = len2 > 0 ? std::clamp((p - k.a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (k.a + s * ab)).norm();
}

void AddPosters(Scene& scene, Rng& rng, const Quad& wall) {
  const int count = rng.UniformInt(1, 2);
  for (int i = 0; i < count; ++i) {
    // Wall axes: one of them is vertical; posters hang 1.1-2.1 m high.
    const bool u_vertical = std::abs(wall.axis_u.z()) > 0.5;
    const Vector3d along = u_vertical ? wall.axis_v : wall.axis_u;
    const double half_along = u_vertical ? wall.half_v : wall.half_u;
    const double w = rng.Uniform(0.5, 1.2), h = rng.Uniform(0.4, 0.9);
    const double s = rng.Uniform(-half_along + w, half_along - w);
    Vector3d centre = wall.centre + s * along + 0.01 * wall.normal();
    centre.z() = rng.Uniform(1.1 + 0.5 * h, 2.1);
    Quad q = MakeQuad(centre, wall.axis_u, wall.axis_v, u_vertical ? 0.5 * h : 0.5 * w, u_vertical ? 0.5 * w : 0.5 * h,
                      scene.AddTexture(ClutterTexture(rng.Seed())));
    scene.static_quads.push_back(q);
  }
}

}  // namespace

void AddRoom(Scene& scene, Rng& rng) {
  const Vector3d L(rng.Uniform(7.0, 8.0), rng.Uniform(6.0, 7.0), rng.Uniform(2.7, 3.0));
  scene.room_size = L;
  const Vector3d X = Vector3d::UnitX(), Y = Vector3d::UnitY(), Z = Vector3d::UnitZ();
  const Vector3d c = 0.5 * L;
  std::vector<Quad>& out = scene.static_quads;
  out.push_back(MakeQuad({c.x(), c.y(), 0}, X, Y, c.x(), c.y(), scene.AddTexture(FloorTexture(rng.Seed()))));
  out.push_back(MakeQuad({c.x(), c.y(), L.z()}, Y, X, c.y(), c.x(), scene.AddTexture(CeilingTexture(rng.Seed()))));
  const Quad walls[4] = {
      MakeQuad({0, c.y(), c.z()}, Y, Z, c.y(), c.z(), scene.AddTexture(WallTexture(rng.Seed()))),
      MakeQuad({L.x(), c.y(), c.z()}, Z, Y, c.z(), c.y(), scene.AddTexture(WallTexture(rng.Seed()))),
      MakeQuad({c.x(), 0, c.z()}, Z, X, c.z(), c.x(), scene.AddTexture(WallTexture(rng.Seed()))),
      MakeQuad({c.x(), L.y(), c.z()}, X, Z, c.x(), c.z(), scene.AddTexture(WallTexture(rng.Seed())))};
  for (const Quad& w : walls) out.push_back(w);
  for (const Quad& w : walls) AddPosters(scene, rng, w);
}

std::optional<Placement> PlaceNearWall(const Scene& scene, Rng& rng, double radius, double max_wall_distance,
                                       std::vector<KeepOut>& keep_outs,
                                       const std::function<bool(const Vector2d&)>& accept) {
  const Vector2d L = scene.room_size.head<2>();
  for (int attempt = 0; attempt < 200; ++attempt) {
    const int wall = rng.UniformInt(0, 3);  // x = 0, x = Lx, y = 0, y = Ly
    const double d = rng.Uniform(radius + 0.05, radius + max_wall_distance);
    const int along_axis = wall < 2 ? 1 : 0;
    const double a = rng.Uniform(radius + 0.05, L[along_axis] - radius - 0.05);
    Vector2d p;
    p[along_axis] = a;
    p[1 - along_axis] = (wall % 2 == 0) ? d : L[1 - along_axis] - d;
    if ((p.array() < radius).any() || (p.array() > L.array() - radius).any()) continue;
    const bool clear = std::all_of(keep_outs.begin(), keep_outs.end(),
                                   [&](const KeepOut& k) { return SegmentDistance(p, k) > k.radius + radius; });
    if (!clear || (accept && !accept(p))) continue;
    keep_outs.push_back({p, p, radius});
    constexpr double kFacing[4] = {0, std::numbers::pi, 0.5 * std::numbers::pi, -0.5 * std::numbers::pi};
    return Placement{p, kFacing[wall]};
  }
  return std::nullopt;
}

void AddClutter(Scene& scene, Rng& rng, int boxes, int panels, std::vector<KeepOut>& keep_outs) {
  for (int i = 0; i < boxes; ++i) {
    const Vector3d size(rng.Uniform(0.3, 1.0), rng.Uniform(0.3, 0.9), rng.Uniform(0.3, 1.4));
    const double yaw = rng.Uniform(-std::numbers::pi, std::numbers::pi);
    const int texture = scene.AddTexture(ClutterTexture(rng.Seed()));
    const bool stacked = rng.Uniform(0, 1) < 0.4;
    const auto spot = PlaceNearWall(scene, rng, 0.5 * size.head<2>().norm(), 1.0, keep_outs);
    if (!spot) continue;
    const Vector3d base(spot->centre.x(), spot->centre.y(), 0);
    AddBox(scene.static_quads, base + Vector3d(0, 0, 0.5 * size.z()), size, yaw, 0, texture);
    if (stacked) {
      const Vector3d top(0.6 * size.x(), 0.6 * size.y(), rng.Uniform(0.2, 0.4));
      AddBox(scene.static_quads, base + Vector3d(0, 0, size.z() + 0.5 * top.z()), top, yaw + rng.Uniform(-0.5, 0.5),
             0, scene.AddTexture(ClutterTexture(rng.Seed())));
    }
  }
  for (int i = 0; i < panels; ++i) {
    const double w = rng.Uniform(1.0, 1.6), h = rng.Uniform(1.3, 2.0);
    const int texture = scene.AddTexture(ClutterTexture(rng.Seed()));
    const auto spot = PlaceNearWall(scene, rng, 0.5 * w, 1.2, keep_outs);
    if (!spot) continue;
    const double yaw = spot->facing + rng.Uniform(-0.6, 0.6);  // roughly facing into the room
    Quad q;
    q.centre = Vector3d(spot->centre.x(), spot->centre.y(), 0.5 * h);
    q.axis_u = Vector3d(-std::sin(yaw), std::cos(yaw), 0);
    q.axis_v = Vector3d::UnitZ();
    q.half_u = 0.5 * w;
    q.half_v = 0.5 * h;
    q.two_sided = true;
    q.texture = texture;
    scene.static_quads.push_back(q);
  }
}

}  // namespace sgslam::synth
