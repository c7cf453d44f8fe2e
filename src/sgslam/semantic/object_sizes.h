// The sizes an object of a class can have, to flag a box that took in the wall or
// the desk behind it (docs/object-map.md lists the ranges and where they come
// from). Ranges bound an object's principal extents (ObjectEstimate::dimensions,
// longest first), so they do not depend on how the map frame is turned.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>

namespace sgslam {

struct SizeRange {
  double longest_min = 0;  // m; not applied to an object never seen whole
  double longest_max = 0;  // m
  double middle_max = 0;   // m, the second extent
};

// The range of a COCO class, or none for a class without one (every size passes).
std::optional<SizeRange> SizeRangeOf(const std::string& class_name);

// Whether dimensions (longest first) fit the class's range; complete false: the
// object was only ever seen cut by the image border, so only the maxima apply.
bool PlausibleSize(const std::string& class_name, const Eigen::Vector3d& dimensions, bool complete = true);

}  // namespace sgslam
