#include "sgslam/synth/presets.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "sgslam/common/error.h"
#include "sgslam/synth/loop_scenes.h"
#include "sgslam/synth/room.h"
#include "sgslam/synth/shapes.h"

namespace sgslam::synth {

namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;
constexpr double kPi = std::numbers::pi;

Oscillation Osc(Rng& rng, double amplitude, double omega) { return {amplitude, omega, rng.Uniform(-kPi, kPi)}; }

// Largest reach from `centre` along +-dir that stays `margin` inside the room.
double MaxReach(const Vector3d& room, const Vector2d& centre, const Vector2d& dir, double margin) {
  double reach = 1e9;
  for (int k = 0; k < 2; ++k) {
    if (std::abs(dir[k]) < 1e-9) continue;
    reach = std::min(reach, (std::min(centre[k] - margin, room[k] - margin - centre[k])) / std::abs(dir[k]));
  }
  return std::max(reach, 0.0);
}

// Handheld-like path in the room's back half: Lissajous wobble (<= 0.35 m/s), gaze
// swinging +-0.25 rad (<= 15 deg/s with pitch and roll) around +x.
void HandheldCamera(Scene& s, Rng& rng) {
  CameraPath& c = s.camera;
  c.line.centre = Vector3d(0.38 * s.room_size.x(), 0.5 * s.room_size.y() + rng.Uniform(-0.3, 0.3), rng.Uniform(1.45, 1.6));
  c.wobble[0] = Osc(rng, 0.3, 0.8);
  c.wobble[1] = Osc(rng, 0.35, 0.7);
  c.wobble[2] = Osc(rng, 0.05, 0.9);
  c.yaw0 = rng.Uniform(-0.1, 0.1);
  c.yaw = Osc(rng, 0.25, 0.9);
  c.pitch0 = -0.17;
  c.pitch = Osc(rng, 0.06, 0.8);
  c.roll = Osc(rng, 0.05, 0.5);
}

// A walker pacing across the camera's mean view at `distance` from it, never far
// from the centre of the view, so that people cover 20-50 % of many frames.
WalkerMotion CrossingWalk(const Scene& s, Rng& rng, double distance, double phase) {
  const CameraPath& c = s.camera;
  const Vector2d gaze(std::cos(c.yaw0), std::sin(c.yaw0));
  const double heading = c.yaw0 + 0.5 * kPi + rng.Uniform(-0.35, 0.35);
  const Vector2d dir = rng.Sign() * Vector2d(std::cos(heading), std::sin(heading));
  const Vector2d lateral(-gaze.y(), gaze.x());
  const Vector2d centre = c.line.centre.head<2>() + distance * gaze + rng.Uniform(-0.2, 0.2) * lateral;
  WalkerMotion w;
  w.path.centre = Vector3d(centre.x(), centre.y(), 0);
  w.path.direction = Vector3d(dir.x(), dir.y(), 0);
  w.path.reach = std::min(rng.Uniform(0.8, 1.1) * distance / 1.7, MaxReach(s.room_size, centre, dir, 0.5));
  w.path.omega = BouncePath::OmegaForSpeed(w.path.reach, rng.Uniform(0.85, 1.15));
  w.path.phase = phase;
  return w;
}

KeepOut PathKeepOut(const BouncePath& p, double radius) {
  return {(p.centre - p.reach * p.direction).head<2>(), (p.centre + p.reach * p.direction).head<2>(), radius};
}

void AddPerson(Scene& s, Rng& rng, const WalkerMotion& motion) {
  const int clothes = s.AddTexture(PersonTexture(rng.Seed()));
  const int head = s.AddTexture(FurnitureTexture(rng.Seed(), 0.55f, 0.7f, 0.9f));
  s.AddObject({.class_name = "person", .class_id = coco::kPerson}, PersonQuads(clothes, head), motion);
}

// static and walkers: the walkers' paths are planned (and kept free) in both, so the
// two presets share room, clutter and camera for a given seed.
void BuildRoomWithWalkers(Scene& s, bool add_walkers) {
  Rng rng(Mix64(s.seed) ^ 0x5a17c0ffeeULL);
  AddRoom(s, rng);
  HandheldCamera(s, rng);
  // Three people at different distances, out of step so they rarely hide each other.
  const double phase = rng.Uniform(-kPi, kPi);
  const WalkerMotion walks[3] = {CrossingWalk(s, rng, rng.Uniform(1.5, 1.8), phase),
                                 CrossingWalk(s, rng, rng.Uniform(2.1, 2.4), phase + 2 * kPi / 3),
                                 CrossingWalk(s, rng, rng.Uniform(2.7, 3.1), phase + 4 * kPi / 3)};
  std::vector<KeepOut> keep = {{s.camera.line.centre.head<2>(), s.camera.line.centre.head<2>(), 0.9}};
  for (const WalkerMotion& w : walks) keep.push_back(PathKeepOut(w.path, 0.5));
  AddClutter(s, rng, rng.UniformInt(5, 7), 1, keep);
  if (!add_walkers) return;
  Rng people(Mix64(s.seed) ^ 0xbeefULL);
  for (const WalkerMotion& w : walks) AddPerson(s, people, w);
}

// rpy: the static room with the camera near one spot, rolling, pitching and
// yawing like TUM's fr1_rpy (peaks near 1.3 rad/s), so that a rolling shutter
// (synth --readout) shears the rows by pixels.
void BuildRpy(Scene& s) {
  BuildRoomWithWalkers(s, /*add_walkers=*/false);
  Rng rng(Mix64(s.seed) ^ 0x0a7e5ULL);
  CameraPath& c = s.camera;
  for (Oscillation& w : c.wobble) w = Osc(rng, 0.04, 1.1);
  c.yaw = Osc(rng, 0.35, 3.0);    // peak 1.05 rad/s
  c.pitch = Osc(rng, 0.15, 3.7);  // 0.55 rad/s
  c.roll = Osc(rng, 0.2, 2.6);    // 0.52 rad/s
}

void BuildDegenerate(Scene& s) {
  Rng rng(Mix64(s.seed) ^ 0xde6e4e7a7eULL);
  AddRoom(s, rng);
  CameraPath& c = s.camera;
  const Vector3d side = Vector3d::UnitY();  // the one direction of travel
  c.line.centre = Vector3d(0.35 * s.room_size.x(), 0.5 * s.room_size.y(), 1.5);
  c.line.direction = side;
  c.line.reach = 0.9;
  c.line.omega = BouncePath::OmegaForSpeed(c.line.reach, rng.Uniform(0.25, 0.35));
  c.yaw = Osc(rng, 0.008, 0.5);  // < 0.5 deg: "little rotation"
  c.pitch0 = -0.08;
  WalkerMotion w;
  w.turns = false;  // a turn would move its sides off the epipolar lines
  w.path.centre = Vector3d(c.line.centre.x() + rng.Uniform(2.2, 2.8), c.line.centre.y(), 0);
  w.path.direction = side;
  w.path.reach = 1.3;
  w.path.omega = BouncePath::OmegaForSpeed(w.path.reach, rng.Uniform(0.9, 1.1));
  w.path.phase = rng.Sign() > 0 ? 0 : kPi;
  const Vector2d cam = c.line.centre.head<2>();
  std::vector<KeepOut> keep = {{cam - side.head<2>(), cam + side.head<2>(), 0.8}, PathKeepOut(w.path, 0.6)};
  AddClutter(s, rng, rng.UniformInt(4, 6), 1, keep);
  AddPerson(s, rng, w);
}

void BuildObjects(Scene& s) {
  Rng rng(Mix64(s.seed) ^ 0x0b1ec75ULL);
  AddRoom(s, rng);
  CameraPath& c = s.camera;
  c.line.centre = Vector3d(0.5 * s.room_size.x(), 0.5 * s.room_size.y(), rng.Uniform(1.4, 1.6));
  c.wobble[0] = Osc(rng, 0.6, 0.45);
  c.wobble[1] = Osc(rng, 0.5, 0.55);
  c.wobble[2] = Osc(rng, 0.06, 0.8);
  c.yaw0 = rng.Uniform(-kPi, kPi);
  c.yaw_rate = rng.Sign() * 0.45;  // 26 deg/s: 260 degrees in the default 300 frames
  c.yaw = Osc(rng, 0.1, 0.7);
  c.pitch0 = -0.3;
  c.pitch = Osc(rng, 0.08, 0.6);
  c.roll = Osc(rng, 0.04, 0.5);
  std::vector<KeepOut> keep = {{c.line.centre.head<2>(), c.line.centre.head<2>(), 1.3}};
  // Objects stand where the gaze sweeps during the first 10 s, at least 0.5 rad from
  // its ends, so each is seen from several views in a default-length sequence.
  const Vector2d room_centre = c.line.centre.head<2>();
  const auto in_sweep = [&](const Vector2d& p) {
    const Vector2d d = p - room_centre;
    const double swept = std::remainder(std::atan2(d.y(), d.x()) - c.yaw0, 2 * kPi) * (c.yaw_rate > 0 ? 1 : -1);
    const double along = swept < 0 ? swept + 2 * kPi : swept;  // angle the gaze turns to reach p
    return along > 0.5 && along < 10.0 * std::abs(c.yaw_rate) - 0.5;
  };
  struct Item {
    const char* name;
    float b, g, r;
  };
  const Item items[] = {{"chair", 0.3f, 0.45f, 0.7f},        {"chair", 0.35f, 0.5f, 0.65f},
                        {"sofa", 0.8f, 0.45f, 0.3f},         {"diningtable", 0.35f, 0.55f, 0.75f},
                        {"tvmonitor", 0.35f, 0.35f, 0.35f},  {"pottedplant", 0.3f, 0.75f, 0.35f},
                        {"pottedplant", 0.35f, 0.7f, 0.4f}};
  for (const Item& item : items) {
    const std::string name = item.name;
    const bool on_cabinet = name == "tvmonitor";
    const double radius = on_cabinet ? 0.65 : FurnitureRadius(name);
    const auto spot = PlaceNearWall(s, rng, radius, 0.6, keep, in_sweep);
    if (!spot) continue;
    const int texture = s.AddTexture(FurnitureTexture(rng.Seed(), item.b, item.g, item.r));
    Vector3d base(spot->centre.x(), spot->centre.y(), 0);
    if (on_cabinet) {  // the cabinet is unlabelled clutter
      const double yaw = 0.5 * kPi * std::round(spot->facing / (0.5 * kPi) - 1);  // as FurnitureQuads turns the tv
      AddBox(s.static_quads, base + Vector3d(0, 0, 0.275), {1.2, 0.45, 0.55}, yaw, 0,
             s.AddTexture(ClutterTexture(rng.Seed())));
      base.z() = 0.55;
    }
    s.AddObject({.class_name = name, .class_id = CocoId(name)}, FurnitureQuads(name, base, spot->facing, texture),
                std::nullopt);
    if (name == "diningtable") {
      const Vector3d top = base + Vector3d(rng.Uniform(-0.3, 0.3), rng.Uniform(-0.2, 0.2), 0.75);
      s.AddObject({.class_name = "bottle", .class_id = coco::kBottle},
                  FurnitureQuads("bottle", top, 0, s.AddTexture(FurnitureTexture(rng.Seed(), 0.5f, 0.7f, 0.3f))),
                  std::nullopt);
    }
  }
}

struct Preset {
  const char* name;
  void (*build)(Scene&);
  PresetDefaults defaults;
};

// The sensor of loop and repeat: a Kinect's depth and its colour camera's
// rolling shutter (the readout measured on fr1_rpy, docs/rolling-shutter.md).
constexpr double kKinectReadout = 0.03;  // s
const Preset kPresets[] = {
    {"static", [](Scene& s) { BuildRoomWithWalkers(s, /*add_walkers=*/false); }, {}},
    {"walkers", [](Scene& s) { BuildRoomWithWalkers(s, /*add_walkers=*/true); }, {}},
    {"degenerate", BuildDegenerate, {}},
    {"objects", BuildObjects, {}},
    {"rpy", BuildRpy, {}},
    {"loop", BuildLoop, {LoopFrames(), kKinectReadout, DepthNoise::kKinect}},
    {"repeat", BuildRepeat, {RepeatFrames(), kKinectReadout, DepthNoise::kKinect}},
};

const Preset& FindPreset(const std::string& name) {
  for (const Preset& p : kPresets) {
    if (name == p.name) return p;
  }
  const std::vector<std::string>& names = PresetNames();
  std::string choices;
  for (std::size_t i = 0; i < names.size(); ++i) {
    choices += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
  }
  throw InputError("unknown synth preset '" + name + "' (choose " + choices + ")");
}

}  // namespace

const std::vector<std::string>& PresetNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (const Preset& p : kPresets) out.push_back(p.name);
    return out;
  }();
  return names;
}

PresetDefaults DefaultsOf(const std::string& preset) { return FindPreset(preset).defaults; }

Scene BuildScene(const std::string& preset, std::uint32_t seed) {
  Scene s;
  s.preset = preset;
  s.seed = seed;
  FindPreset(preset).build(s);
  return s;
}

}  // namespace sgslam::synth
