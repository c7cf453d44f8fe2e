#include "sgslam/synth/motion.h"

#include <cmath>
#include <numbers>

namespace sgslam::synth {

namespace {
constexpr double kBounceK = 0.97;
const double kAsinK = std::asin(kBounceK);
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

Eigen::Vector3d CameraPath::Position(double t) const {
  return line.Position(t) + Eigen::Vector3d(wobble[0](t), wobble[1](t), wobble[2](t));
}

Eigen::Vector3d CameraPath::Target(double t) const {
  const double azimuth = yaw0 + yaw_rate * t + yaw(t);
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
