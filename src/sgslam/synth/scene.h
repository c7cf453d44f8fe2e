// A synthetic scene: a textured room, unlabelled clutter, labelled objects (static
// furniture or walking people) and the camera's path. Built by a preset
// (presets.h); rendered per frame by the renderer (renderer.h).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "sgslam/synth/geometry.h"
#include "sgslam/synth/motion.h"
#include "sgslam/synth/texture.h"

namespace sgslam::synth {

// A labelled object, as objects_gt.json lists it.
struct ObjectInfo {
  int id = 0;  // 1-based; the object-id image holds it
  std::string class_name;
  int class_id = -1;  // COCO id (coco.names order)
  bool dynamic = false;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  // m, world; of the axis-aligned box (static objects)
  Eigen::Vector3d size = Eigen::Vector3d::Zero();      // m; world axis-aligned box (static), own frame (dynamic)
};

struct SceneObject {
  ObjectInfo info;
  std::vector<Quad> quads;             // world frame when static, object frame when it moves
  std::optional<WalkerMotion> motion;  // set for moving objects

  SE3 Pose(double t) const { return motion ? motion->Pose(t) : SE3(); }  // T_w_o
};

struct Scene {
  std::string preset;
  std::uint32_t seed = 0;
  Eigen::Vector3d room_size = Eigen::Vector3d::Zero();  // m; the room spans [0, size] on each axis
  std::vector<Texture> textures;
  std::vector<Quad> static_quads;  // room, posters, panels, unlabelled clutter
  std::vector<SceneObject> objects;  // labelled; objects[k].info.id == k + 1
  CameraPath camera;

  int AddTexture(const Texture& texture) {
    textures.push_back(texture);
    return static_cast<int>(textures.size()) - 1;
  }
  // Adds a labelled object made of boxes and fills in its id, centroid and size.
  SceneObject& AddObject(ObjectInfo info, std::vector<Quad> quads, std::optional<WalkerMotion> motion);

  // Every surface in the world frame at time t (s).
  std::vector<Quad> SurfacesAt(double t) const;
  bool IsDynamic(int object_id) const {
    return object_id > 0 && object_id <= static_cast<int>(objects.size()) && objects[object_id - 1].info.dynamic;
  }
};

}  // namespace sgslam::synth
