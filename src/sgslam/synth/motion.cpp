#include "sgslam/synth/motion.h"

#include <cmath>
#include <numbers>

namespace sgslam::synth {

namespace {
constexpr double kBounceK = 0.97;
const double kAsinK = std::asin(kBounceK);
constexpr double kPi = std::numbers::pi;

struct LoopPoint {
  Eigen::Vector2d p;
  double heading;
};

// Walks the four sides (a straight, then a quarter circle turning left) from the
// start of the -y side's straight.
LoopPoint Locate(const LoopPath& loop, double s) {
  const double r = loop.corner, arc = 0.5 * kPi * r;
  const Eigen::Vector2d straight = 2 * (loop.half_size - Eigen::Vector2d::Constant(r));
  double u = s + 0.5 * straight.x();
  u -= loop.Length() * std::floor(u / loop.Length());
  Eigen::Vector2d p = loop.centre - loop.half_size + Eigen::Vector2d(r, 0);
  for (int k = 0; k < 4; ++k) {
    const double heading = 0.5 * kPi * k;
    const Eigen::Vector2d d(std::cos(heading), std::sin(heading)), n(-d.y(), d.x());
    const double length = straight[k % 2];
    if (u <= length) return {p + u * d, heading};
    u -= length;
    p += length * d;
    if (u <= arc) return {p + r * std::sin(u / r) * d + r * (1 - std::cos(u / r)) * n, heading + u / r};
    u -= arc;
    p += r * (d + n);
  }
  return {p, 2 * kPi};  // rounding at the very end of the lap
}

double CosineRamp(double x) { return x <= 0 ? 0 : x >= 1 ? 1 : 0.5 * (1 - std::cos(kPi * x)); }

}  // namespace

double Oscillation::operator()(double t) const { return amplitude * std::sin(omega * t + phase); }
double Oscillation::Rate(double t) const { return amplitude * omega * std::cos(omega * t + phase); }

double BouncePath::Offset(double t) const { return reach * std::asin(kBounceK * std::sin(omega * t + phase)) / kAsinK; }

double BouncePath::Speed(double t) const {
  const double a = omega * t + phase;
  const double s = kBounceK * std::sin(a);
  return reach * kBounceK * omega * std::cos(a) / (std::sqrt(1 - s * s) * kAsinK);
}

double BouncePath::OmegaForSpeed(double reach, double speed) {
  // A full period covers 4 * reach.
  return reach > 0 ? speed * 2 * std::numbers::pi / (4 * reach) : 0;
}

double LoopPath::Length() const {
  const Eigen::Vector2d straight = 2 * (half_size - Eigen::Vector2d::Constant(corner));
  return 2 * (straight.x() + straight.y()) + 2 * kPi * corner;
}

Eigen::Vector2d LoopPath::Point(double s) const { return Locate(*this, s).p; }

double LoopPath::Heading(double s) const { return Locate(*this, s).heading; }

double LoopPath::GazeHeading(double s) const {
  const double length = Length(), arc = 0.5 * kPi * corner, width = arc + 2 * turn_margin;
  const double a = 2 * (half_size.x() - corner), b = 2 * (half_size.y() - corner);
  const double middles[4] = {0.5 * (a + arc), 0.5 * (a + arc) + arc + b, 0.5 * (a + arc) + 2 * arc + a + b,
                             0.5 * (a + arc) + 3 * arc + a + 2 * b};  // of the corners' arcs
  const double laps = std::floor(s / length), u = s - laps * length;
  // The previous, this and the next lap's corners: ramps that cross the lap's start.
  double heading = 2 * kPi * (laps - 1);
  for (double lap = -1; lap <= 1; ++lap) {
    for (double m : middles) heading += 0.5 * kPi * CosineRamp((u - m - lap * length) / width + 0.5);
  }
  return heading;
}

Eigen::Vector3d CameraPath::Position(double t) const {
  Eigen::Vector3d p = line.Position(t) + Eigen::Vector3d(wobble[0](t), wobble[1](t), wobble[2](t));
  if (loop.speed > 0) p.head<2>() += loop.Point(loop.Arc(t));
  return p;
}

Eigen::Vector3d CameraPath::Target(double t) const {
  double azimuth = yaw0 + yaw_rate * t + yaw(t);
  if (loop.speed > 0) azimuth += loop.GazeHeading(loop.Arc(t));
  const double elevation = pitch0 + pitch(t);
  const Eigen::Vector3d gaze(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
                             std::sin(elevation));
  return Position(t) + gaze_distance * gaze;
}

SE3 CameraPath::Pose(double t) const { return LookAt(Position(t), Target(t), roll(t)); }

SE3 LookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target, double roll) {
  const Eigen::Vector3d z = (target - eye).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();  // right, level
  const Eigen::Vector3d y = z.cross(x);                                      // down
  Eigen::Matrix3d R_w_c;
  R_w_c << x, y, z;
  return SE3(R_w_c * Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ()).toRotationMatrix(), eye);
}

SE3 WalkerMotion::Pose(double t) const {
  const Eigen::Vector3d& d = path.direction;
  double yaw = std::atan2(-d.x(), d.y());  // object y axis along the path
  if (turns) yaw += 0.5 * std::numbers::pi * (1 - std::tanh(path.Speed(t) / 0.25));
  return SE3(Eigen::Matrix3d(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ())), path.Position(t));
}

}  // namespace sgslam::synth
