// Scene geometry of the synthetic sequences: every surface is a textured rectangle
// ("quad"); boxes are six of them. Rendering casts one ray per pixel against them.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "sgslam/common/se3.h"

namespace sgslam::synth {

struct Quad {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis_u = Eigen::Vector3d::UnitX();  // unit; axis_u x axis_v is the visible side
  Eigen::Vector3d axis_v = Eigen::Vector3d::UnitY();  // unit, orthogonal to axis_u
  double half_u = 0, half_v = 0;                      // m
  bool two_sided = false;
  int object = 0;   // labelled object id (1-based), 0 for unlabelled static surfaces
  int texture = 0;  // index into Scene::textures
  Eigen::Vector2d texture_offset = Eigen::Vector2d::Zero();  // m, added to the surface coordinates

  Eigen::Vector3d normal() const { return axis_u.cross(axis_v); }
  // Surface coordinates (m) of a point on the quad: the texture is a function of them.
  Eigen::Vector2d SurfaceCoordinates(const Eigen::Vector3d& p) const {
    const Eigen::Vector3d d = p - centre;
    return {axis_u.dot(d) + texture_offset.x(), axis_v.dot(d) + texture_offset.y()};
  }
  bool Contains(const Eigen::Vector3d& p_on_plane, double tolerance = 0) const {
    const Eigen::Vector3d d = p_on_plane - centre;
    return std::abs(axis_u.dot(d)) <= half_u + tolerance && std::abs(axis_v.dot(d)) <= half_v + tolerance;
  }
  void Corners(Eigen::Vector3d corners[4]) const;
};

// A quad with half sides hu, hv along u, v (unit, orthogonal; u x v its visible side).
Quad MakeQuad(const Eigen::Vector3d& centre, const Eigen::Vector3d& u, const Eigen::Vector3d& v, double hu, double hv,
              int texture);

// The quad moved rigidly by T_b_a (its coordinates given in frame a, result in b).
Quad Transformed(const SE3& T_b_a, const Quad& quad);

// Appends the six outward faces of a box with sides `size` (m), centred at `centre`,
// turned by `yaw` about z. Faces get different texture offsets so they differ.
void AddBox(std::vector<Quad>& quads, const Eigen::Vector3d& centre, const Eigen::Vector3d& size, double yaw,
            int object, int texture);

// Axis-aligned bounds of a set of quads.
void Bounds(const std::vector<Quad>& quads, Eigen::Vector3d& min, Eigen::Vector3d& max);

// Ray from the origin along `direction`: depth parameter t of the hit (p = t * direction)
// or a negative value when it misses the quad or hits its back side.
double IntersectRay(const Quad& quad, const Eigen::Vector3d& origin, const Eigen::Vector3d& direction);

}  // namespace sgslam::synth
