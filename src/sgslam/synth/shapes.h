// Box-built shapes of the labelled objects: a person (for the walkers) and
// furniture-like objects of a few COCO classes, plus the COCO ids used here
// (0-based, in the order of coco.names; hard-coded so nothing is read at run time).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "sgslam/synth/geometry.h"

namespace sgslam::synth {

namespace coco {
constexpr int kPerson = 0;
constexpr int kBottle = 39;
constexpr int kChair = 56;
constexpr int kSofa = 57;
constexpr int kPottedPlant = 58;
constexpr int kDiningTable = 60;
constexpr int kTvMonitor = 62;
}  // namespace coco

// COCO id of one of the names above ("person", "chair", ...); -1 for others.
int CocoId(const std::string& class_name);

// A person 0.68 x 0.28 x 1.75 m (legs, torso, arms, head) in its own frame: x to its
// side, y forward, z up, feet at z = 0.
std::vector<Quad> PersonQuads(int clothes_texture, int head_texture);

// Furniture of class chair, sofa, diningtable, tvmonitor, pottedplant or bottle,
// standing on `base` (its lowest point) and facing `facing` rounded to a multiple of
// 90 degrees, so every box stays axis-aligned and the object's world box is exact.
std::vector<Quad> FurnitureQuads(const std::string& class_name, const Eigen::Vector3d& base, double facing,
                                 int texture);

// Radius (m) of the floor footprint of a furniture class.
double FurnitureRadius(const std::string& class_name);

}  // namespace sgslam::synth
