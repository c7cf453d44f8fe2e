// Smooth motions of the synthetic sequences: the camera's 6-DoF path and the walkers'
// back-and-forth walks. Everything is an analytic function of time, so any frame can
// be rendered on its own (frames render in parallel) and velocities are exact.
#pragma once

#include <Eigen/Core>

#include "sgslam/common/se3.h"

namespace sgslam::synth {

struct Oscillation {
  double amplitude = 0, omega = 0, phase = 0;  // any unit, rad/s, rad
  double operator()(double t) const;
  double Rate(double t) const;
};

// Back and forth along a line: s(t) = reach * asin(k sin(w t + phase)) / asin(k), a
// near-constant speed with smooth turns at both ends (k = 0.97).
struct BouncePath {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();  // unit
  double reach = 0;                                       // m, farthest distance from centre
  double omega = 0, phase = 0;                            // rad/s, rad

  double Offset(double t) const;
  double Speed(double t) const;  // signed, m/s along direction
  Eigen::Vector3d Position(double t) const { return centre + Offset(t) * direction; }
  Eigen::Vector3d Velocity(double t) const { return Speed(t) * direction; }
  // The omega that gives this mean speed (m/s) over a full back-and-forth.
  static double OmegaForSpeed(double reach, double speed);
};

// A closed loop walked anticlockwise (seen from above) at constant speed: a
// rectangle with rounded corners. Arc length 0 is the middle of the -y side.
struct LoopPath {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();     // m, of the enclosing rectangle
  Eigen::Vector2d half_size = Eigen::Vector2d::Zero();  // m, of the enclosing rectangle
  double corner = 1.0;                                  // m, radius of the rounded corners
  double speed = 0;                                     // m/s; 0: no loop
  double start = 0;                                     // m, arc length at t = 0
  // m: the gaze turns by 90 degrees over each corner's arc and this much of the
  // straights either side, with a cosine ramp, so its rate is continuous.
  double turn_margin = 0.6;

  double Length() const;                                    // m, one lap
  double Arc(double t) const { return start + speed * t; }  // m, at time t (s)
  Eigen::Vector2d Point(double s) const;                    // m, at arc length s (periodic)
  double Heading(double s) const;                           // rad, tangent azimuth (its rate jumps at the corners)
  double GazeHeading(double s) const;                       // rad, smoothed and unwrapped: + 2 pi a lap
};

// Camera position, look-at target and roll, all smooth in time.
struct CameraPath {
  BouncePath line;              // the mean translation (reach 0: none)
  LoopPath loop;                // added to line's position when loop.speed > 0
  Oscillation wobble[3];        // m, added to the position along world x, y, z
  double yaw0 = 0;              // rad, gaze azimuth about world z (0: along +x); on a loop, from its GazeHeading
  double yaw_rate = 0;          // rad/s, steady turn
  Oscillation yaw;              // rad, added to the azimuth
  double pitch0 = 0;            // rad, gaze elevation (negative: looking down)
  Oscillation pitch;            // rad
  Oscillation roll;             // rad, about the optical axis
  double gaze_distance = 3.0;   // m, distance of the look-at target

  Eigen::Vector3d Position(double t) const;
  Eigen::Vector3d Target(double t) const;
  SE3 Pose(double t) const;  // T_w_c, camera x right, y down, z forward; world z up
};

// T_w_c of a camera at `eye` looking at `target`, turned by `roll` about its z axis.
SE3 LookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target, double roll);

// A walker: walks a BouncePath facing along it, optionally turning round (smoothly)
// at the ends. Object frame: x to its side, y forward, z up, origin on the floor.
struct WalkerMotion {
  BouncePath path;
  bool turns = true;
  SE3 Pose(double t) const;  // T_w_o
};

}  // namespace sgslam::synth
