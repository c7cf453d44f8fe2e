// Building blocks of the preset scenes: the room (walls, floor, ceiling, posters),
// placement of things on the floor away from the camera's and walkers' paths, and
// unlabelled clutter (boxes and free-standing panels).
#pragma once

#include <Eigen/Core>
#include <array>
#include <functional>
#include <optional>
#include <vector>

#include "sgslam/synth/random.h"
#include "sgslam/synth/scene.h"

namespace sgslam::synth {

// A region of the floor to keep free: the points within `radius` of segment a-b.
struct KeepOut {
  Eigen::Vector2d a, b;
  double radius;
};

struct Placement {
  Eigen::Vector2d centre;  // m, floor
  double facing;           // rad, yaw of the direction from the nearest wall into the room
};

// Sets the room size (7-8 x 6-7 x 2.7-3 m) and adds its six inward-facing surfaces
// and a few posters on the walls.
void AddRoom(Scene& scene, Rng& rng);

// Sets the room size to `size` (m) and adds floor, ceiling and walls, facing in;
// returns the walls (x = 0, x = size.x, y = 0, y = size.y).
std::array<Quad, 4> AddRoomShell(Scene& scene, Rng& rng, const Eigen::Vector3d& size);

// Posters in dark frames along a wall, 0.85-2.05 m high (eye level for a hand-held
// camera), one in each `slot`-wide (m) stretch but one in five left bare.
void AddPosterRow(Scene& scene, Rng& rng, const Quad& wall, double slot);

// A free spot for a footprint of `radius` within `max_wall_distance` of a wall, clear
// of the keep-outs and accepted by `accept` (when given); the spot is added to the
// keep-outs. nullopt when none is found.
std::optional<Placement> PlaceNearWall(const Scene& scene, Rng& rng, double radius, double max_wall_distance,
                                       std::vector<KeepOut>& keep_outs,
                                       const std::function<bool(const Eigen::Vector2d&)>& accept = nullptr);

// Unlabelled cabinets and shelves (boxes 0.35-0.6 m deep, 0.6-1.6 m wide, 0.5-1.9 m
// high) standing against a wall 0.8-2.5 m apart, 0.7 m or more from its ends; their
// footprints are added to the keep-outs.
void AddWallFurniture(Scene& scene, Rng& rng, const Quad& wall, std::vector<KeepOut>& keep_outs);

// Unlabelled boxes (some with a smaller box on top) and standing panels.
void AddClutter(Scene& scene, Rng& rng, int boxes, int panels, std::vector<KeepOut>& keep_outs);

}  // namespace sgslam::synth
