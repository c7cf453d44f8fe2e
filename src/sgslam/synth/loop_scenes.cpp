#include "sgslam/synth/loop_scenes.h"

#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include "sgslam/synth/room.h"

namespace sgslam::synth {

namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;
constexpr double kPi = std::numbers::pi;
constexpr double kWallToPath = 1.6;  // m, from the hall's walls to the loop
constexpr double kPathClear = 0.6;   // m, kept free either side of the camera's path
// The walls are seen from 1.2-4.5 m, nearer than in the room presets: finer
// textures give about as many corners per image (FAST-20 ~1000-2000, fr1_rpy 200-1000).
constexpr float kTextureScale = 0.6f;

Oscillation Osc(Rng& rng, double amplitude, double omega) { return {amplitude, omega, rng.Uniform(-kPi, kPi)}; }

// Hand-held at walking pace: a 1.75 Hz bob, a body sway in roll, slow swings of
// the gaze, and a +-4 cm sideways sway that repeats every `sway_seconds`.
void WalkingCamera(CameraPath& c, Rng& rng, double sway_seconds) {
  const double w = 2 * kPi / sway_seconds;
  c.wobble[0] = Osc(rng, 0.04, 3 * w);
  c.wobble[1] = Osc(rng, 0.04, 4 * w);
  c.wobble[2] = Osc(rng, 0.01, 2 * kPi * 1.75);
  c.yaw = Osc(rng, 0.06, 2 * kPi / 13);
  c.pitch0 = -0.15;  // the floor along the walls in view
  c.pitch = Osc(rng, 0.04, 2 * kPi / 7.3);
  c.roll = Osc(rng, 0.02, 2 * kPi * 0.875);
}

// The floor around the loop, as segments between points 0.5 m or less apart.
std::vector<KeepOut> LoopKeepOuts(const LoopPath& loop, double radius) {
  const int n = static_cast<int>(std::ceil(loop.Length() / 0.5));
  std::vector<KeepOut> keep;
  for (int i = 0; i < n; ++i) {
    keep.push_back({loop.Point(loop.Length() * i / n), loop.Point(loop.Length() * (i + 1) / n), radius});
  }
  return keep;
}

// Copies the quads added since `first` to `copies` more places, `step` apart.
void Repeat(Scene& s, std::size_t first, int copies, const Vector3d& step) {
  const std::size_t end = s.static_quads.size();
  for (int k = 1; k <= copies; ++k) {
    for (std::size_t i = first; i < end; ++i) {
      Quad q = s.static_quads[i];
      q.centre += k * step;
      s.static_quads.push_back(q);
    }
  }
}

// One corridor module, x in [0, period]: its own stretch of floor, ceiling and
// both walls (with a hair of overlap, so no crack opens between modules), posters
// on both walls and a box against the left (y = width) wall.
void AddCorridorModule(Scene& s, Rng& rng, double period, const Vector3d& L) {
  const Vector3d X = Vector3d::UnitX(), Y = Vector3d::UnitY(), Z = Vector3d::UnitZ();
  const double hx = 0.5 * period + 5e-4, y = 0.5 * L.y(), z = 0.5 * L.z(), x = 0.5 * period;
  std::vector<Quad>& out = s.static_quads;
  out.push_back(MakeQuad({x, y, 0}, X, Y, hx, y, s.AddTexture(FloorTexture(rng.Seed()))));
  out.push_back(MakeQuad({x, y, L.z()}, Y, X, y, hx, s.AddTexture(CeilingTexture(rng.Seed()))));
  const Quad right = MakeQuad({x, 0, z}, Z, X, z, hx, s.AddTexture(WallTexture(rng.Seed())));
  const Quad left = MakeQuad({x, L.y(), z}, X, Z, hx, z, s.AddTexture(WallTexture(rng.Seed())));
  out.push_back(right);
  out.push_back(left);
  AddPosterRow(s, rng, left, 0.5 * period);
  AddPosterRow(s, rng, right, 0.5 * period);
  const Vector3d box(rng.Uniform(0.5, 0.8), rng.Uniform(0.35, 0.5), rng.Uniform(0.5, 1.0));
  const Vector3d at(rng.Uniform(0.2, 0.8) * period, L.y() - 0.5 * box.y() - 0.05, 0.5 * box.z());
  AddBox(out, at, box, 0, 0, s.AddTexture(ClutterTexture(rng.Seed())));
}

}  // namespace

void BuildLoop(Scene& s) {
  Rng rng(Mix64(s.seed) ^ 0x100bc1053dULL);
  const Vector3d L(rng.Uniform(11.0, 12.0), rng.Uniform(7.0, 7.5), rng.Uniform(2.7, 3.0));
  const std::array<Quad, 4> walls = AddRoomShell(s, rng, L);
  for (const Quad& wall : walls) AddPosterRow(s, rng, wall, 1.8);
  CameraPath& c = s.camera;
  LoopPath& loop = c.loop;
  loop.centre = 0.5 * L.head<2>();
  loop.half_size = loop.centre - Vector2d::Constant(kWallToPath);
  loop.corner = 1.2;
  loop.speed = loop.Length() / kLoopLapSeconds;
  loop.start = rng.Uniform(0, loop.Length());
  c.line.centre = Vector3d(0, 0, rng.Uniform(1.45, 1.6));
  c.yaw0 = -0.9;  // the walls on the right of the anticlockwise walk
  WalkingCamera(c, rng, kLoopLapSeconds);
  std::vector<KeepOut> keep = LoopKeepOuts(loop, kPathClear);
  for (const Quad& wall : walls) AddWallFurniture(s, rng, wall, keep);
  AddClutter(s, rng, 14, 3, keep);  // those that fit between the walls, furniture and path
  for (Texture& t : s.textures) t.scale *= kTextureScale;
}

void BuildRepeat(Scene& s) {
  Rng rng(Mix64(s.seed) ^ 0x4e9ea75ULL);
  const double period = rng.Uniform(3.3, 3.7);
  const Vector3d L(kRepeatModules * period, rng.Uniform(2.9, 3.1), rng.Uniform(2.7, 3.0));
  s.room_size = L;
  const std::size_t first = s.static_quads.size();
  AddCorridorModule(s, rng, period, L);
  Repeat(s, first, kRepeatModules - 1, period * Vector3d::UnitX());
  const Vector3d Y = Vector3d::UnitY(), Z = Vector3d::UnitZ(), c = 0.5 * L;
  s.static_quads.push_back(MakeQuad({0, c.y(), c.z()}, Y, Z, c.y(), c.z(), s.AddTexture(WallTexture(rng.Seed()))));
  s.static_quads.push_back(MakeQuad({L.x(), c.y(), c.z()}, Z, Y, c.z(), c.y(), s.AddTexture(WallTexture(rng.Seed()))));
  CameraPath& cam = s.camera;
  cam.line.centre = Vector3d(c.x(), c.y(), rng.Uniform(1.45, 1.6));
  cam.line.direction = Vector3d::UnitX();
  cam.line.reach = 0.5 * (kRepeatModules - 1) * period;
  cam.line.omega = kPi / kRepeatSeconds;  // half a back-and-forth: one way
  cam.line.phase = -0.5 * kPi;            // from -reach
  cam.yaw0 = 0.95;                        // the left (y = width) wall
  WalkingCamera(cam, rng, 23);
  for (Texture& t : s.textures) t.scale *= kTextureScale;
}

}  // namespace sgslam::synth
