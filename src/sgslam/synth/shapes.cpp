#include "sgslam/synth/shapes.h"

#include <cmath>
#include <map>
#include <numbers>

#include "sgslam/common/error.h"

namespace sgslam::synth {

namespace {

using Eigen::Vector3d;

struct Part {
  Vector3d centre;  // m, object frame: x side, y forward, z up
  Vector3d size;    // m
};

const std::map<std::string, std::vector<Part>>& FurnitureParts() {
  static const std::map<std::string, std::vector<Part>> parts = {
      {"chair",
       {{{0, 0, 0.45}, {0.46, 0.46, 0.05}},
        {{0.2, 0.2, 0.2125}, {0.04, 0.04, 0.425}},
        {{-0.2, 0.2, 0.2125}, {0.04, 0.04, 0.425}},
        {{0.2, -0.2, 0.2125}, {0.04, 0.04, 0.425}},
        {{-0.2, -0.2, 0.2125}, {0.04, 0.04, 0.425}},
        {{0, -0.205, 0.725}, {0.46, 0.05, 0.5}}}},
      {"sofa",
       {{{0, 0, 0.21}, {1.8, 0.85, 0.42}},
        {{0, -0.325, 0.645}, {1.8, 0.2, 0.45}},
        {{0.8, 0.1, 0.53}, {0.2, 0.65, 0.22}},
        {{-0.8, 0.1, 0.53}, {0.2, 0.65, 0.22}}}},
      {"diningtable",
       {{{0, 0, 0.725}, {1.4, 0.8, 0.05}},
        {{0.64, 0.34, 0.35}, {0.06, 0.06, 0.7}},
        {{-0.64, 0.34, 0.35}, {0.06, 0.06, 0.7}},
        {{0.64, -0.34, 0.35}, {0.06, 0.06, 0.7}},
        {{-0.64, -0.34, 0.35}, {0.06, 0.06, 0.7}}}},
      {"tvmonitor", {{{0, 0, 0.37}, {1.0, 0.07, 0.6}}, {{0, 0, 0.035}, {0.3, 0.2, 0.07}}}},
      {"pottedplant",
       {{{0, 0, 0.175}, {0.32, 0.32, 0.35}}, {{0, 0, 0.6}, {0.55, 0.55, 0.5}}, {{0, 0, 1.0}, {0.35, 0.35, 0.3}}}},
      {"bottle", {{{0, 0, 0.125}, {0.08, 0.08, 0.25}}}},
  };
  return parts;
}

}  // namespace

int CocoId(const std::string& class_name) {
  static const std::map<std::string, int> ids = {
      {"person", coco::kPerson},       {"bottle", coco::kBottle},           {"chair", coco::kChair},
      {"sofa", coco::kSofa},           {"pottedplant", coco::kPottedPlant}, {"diningtable", coco::kDiningTable},
      {"tvmonitor", coco::kTvMonitor}};
  const auto it = ids.find(class_name);
  return it == ids.end() ? -1 : it->second;
}

std::vector<Quad> PersonQuads(int clothes_texture, int head_texture) {
  std::vector<Quad> q;
  AddBox(q, {0.11, 0, 0.425}, {0.17, 0.22, 0.85}, 0, 0, clothes_texture);
  AddBox(q, {-0.11, 0, 0.425}, {0.17, 0.22, 0.85}, 0, 0, clothes_texture);
  AddBox(q, {0, 0, 1.16}, {0.46, 0.28, 0.62}, 0, 0, clothes_texture);
  AddBox(q, {0.29, 0, 1.18}, {0.1, 0.14, 0.58}, 0, 0, clothes_texture);
  AddBox(q, {-0.29, 0, 1.18}, {0.1, 0.14, 0.58}, 0, 0, clothes_texture);
  AddBox(q, {0, 0, 1.61}, {0.2, 0.23, 0.28}, 0, 0, head_texture);
  return q;
}

std::vector<Quad> FurnitureQuads(const std::string& class_name, const Vector3d& base, double facing, int texture) {
  const auto it = FurnitureParts().find(class_name);
  if (it == FurnitureParts().end()) throw Error("synth: no furniture shape for class '" + class_name + "'");
  // Object y axis along the facing direction, turned by a multiple of 90 degrees.
  const double quarter = 0.5 * std::numbers::pi;
  const double yaw = quarter * std::round((facing - quarter) / quarter);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(yaw, Vector3d::UnitZ()).toRotationMatrix();
  std::vector<Quad> quads;
  for (const Part& p : it->second) AddBox(quads, base + R * p.centre, p.size, yaw, 0, texture);
  return quads;
}

double FurnitureRadius(const std::string& class_name) {
  const auto it = FurnitureParts().find(class_name);
  if (it == FurnitureParts().end()) return 0.5;
  double r = 0;
  for (const Part& p : it->second) r = std::max(r, p.centre.head<2>().norm() + 0.5 * p.size.head<2>().norm());
  return r;
}

}  // namespace sgslam::synth
