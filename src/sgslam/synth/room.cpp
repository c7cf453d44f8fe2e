#include "sgslam/synth/room.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace sgslam::synth {

namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

double SegmentDistance(const Vector2d& p, const KeepOut& k) {
  const Vector2d ab = k.b - k.a;
  const double len2 = ab.squaredNorm();
  const double s = len2 > 0 ? std::clamp((p - k.a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (k.a + s * ab)).norm();
}

// A poster w x h (m) at `s` along the wall from its centre, its lower edge
// `bottom` m or more above the floor, its centre `centre_max` m or less.
void AddPoster(Scene& scene, Rng& rng, const Quad& wall, double s, double w, double h, double bottom = 1.1,
               double centre_max = 2.1) {
  // Wall axes: one of them is vertical.
  const bool u_vertical = std::abs(wall.axis_u.z()) > 0.5;
  const Vector3d along = u_vertical ? wall.axis_v : wall.axis_u;
  Vector3d centre = wall.centre + s * along + 0.01 * wall.normal();
  centre.z() = rng.Uniform(bottom + 0.5 * h, centre_max);
  Quad q = MakeQuad(centre, wall.axis_u, wall.axis_v, u_vertical ? 0.5 * h : 0.5 * w, u_vertical ? 0.5 * w : 0.5 * h,
                    scene.AddTexture(ClutterTexture(rng.Seed())));
  scene.static_quads.push_back(q);
}

double HalfAlong(const Quad& wall) { return std::abs(wall.axis_u.z()) > 0.5 ? wall.half_v : wall.half_u; }

void AddPosters(Scene& scene, Rng& rng, const Quad& wall) {
  const int count = rng.UniformInt(1, 2);
  for (int i = 0; i < count; ++i) {
    const double half_along = HalfAlong(wall);
    const double w = rng.Uniform(0.5, 1.2), h = rng.Uniform(0.4, 0.9);
    AddPoster(scene, rng, wall, rng.Uniform(-half_along + w, half_along - w), w, h);
  }
}

}  // namespace

void AddRoom(Scene& scene, Rng& rng) {
  const Vector3d L(rng.Uniform(7.0, 8.0), rng.Uniform(6.0, 7.0), rng.Uniform(2.7, 3.0));
  for (const Quad& w : AddRoomShell(scene, rng, L)) AddPosters(scene, rng, w);
}

std::array<Quad, 4> AddRoomShell(Scene& scene, Rng& rng, const Vector3d& L) {
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
  return {walls[0], walls[1], walls[2], walls[3]};
}

void AddPosterRow(Scene& scene, Rng& rng, const Quad& wall, double slot) {
  const double half_along = HalfAlong(wall);
  const int slots = static_cast<int>(std::floor(2 * half_along / slot));
  Texture dark;  // of the frames: near-black
  dark.colourfulness = 0;
  dark.min_level = 0.08f, dark.max_level = 0.12f;
  const int frame_texture = scene.AddTexture(dark);
  for (int i = 0; i < slots; ++i) {
    if (rng.Uniform(0, 1) < 0.2) continue;  // a bare stretch now and then
    const double w = rng.Uniform(0.5, std::min(1.2, slot - 0.3)), h = rng.Uniform(0.4, 0.9);
    const double centre = -half_along + (i + 0.5) * (2 * half_along / slots);  // of the slot
    AddPoster(scene, rng, wall, centre + rng.Uniform(-0.5, 0.5) * (slot - 0.3 - w), w, h, 0.85, 1.6);
    Quad frame = scene.static_quads.back();  // 3 cm wider each side, just behind the poster
    frame.centre -= 0.005 * wall.normal();
    frame.half_u += 0.03;
    frame.half_v += 0.03;
    frame.texture = frame_texture;
    scene.static_quads.push_back(frame);
  }
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

void AddWallFurniture(Scene& scene, Rng& rng, const Quad& wall, std::vector<KeepOut>& keep_outs) {
  const double half_along = HalfAlong(wall);
  const Vector3d along = std::abs(wall.axis_u.z()) > 0.5 ? wall.axis_v : wall.axis_u;
  const Vector3d normal = wall.normal();
  double at = -half_along + 0.7 + rng.Uniform(0, 1.5);  // the next piece's start along the wall
  while (true) {
    const Vector3d size(rng.Uniform(0.35, 0.6), rng.Uniform(0.6, 1.6), rng.Uniform(0.5, 1.9));  // deep, wide, high
    const int texture = scene.AddTexture(ClutterTexture(rng.Seed()));
    if (at + size.y() > half_along - 0.7) return;
    Vector3d centre = wall.centre + (at + 0.5 * size.y()) * along + (0.5 * size.x() + 0.01) * normal;
    centre.z() = 0.5 * size.z();
    AddBox(scene.static_quads, centre, size, std::atan2(normal.y(), normal.x()), 0, texture);
    const Vector2d half_width = 0.5 * size.y() * along.head<2>();
    keep_outs.push_back({centre.head<2>() - half_width, centre.head<2>() + half_width, 0.5 * size.x()});
    at += size.y() + rng.Uniform(0.8, 2.5);
  }
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
