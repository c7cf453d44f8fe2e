#include "sgslam/semantic/object_sizes.h"

#include <algorithm>
#include <array>
#include <string_view>

namespace sgslam {

namespace {

struct ClassSize {
  std::string_view name;
  SizeRange range;
};

// Generous bounds on real objects' extents (docs/object-map.md, "Sizes"), plus the
// few centimetres a depth segment adds; the detector's indoor classes.
constexpr std::array kSizes = {
    ClassSize{"tvmonitor", {0.25, 1.30, 0.85}},   ClassSize{"laptop", {0.20, 0.50, 0.45}},
    ClassSize{"keyboard", {0.25, 0.60, 0.30}},    ClassSize{"mouse", {0.04, 0.18, 0.12}},
    ClassSize{"remote", {0.06, 0.30, 0.12}},      ClassSize{"cell phone", {0.06, 0.22, 0.12}},
    ClassSize{"cup", {0.04, 0.22, 0.18}},         ClassSize{"bottle", {0.06, 0.45, 0.20}},
    ClassSize{"wine glass", {0.06, 0.30, 0.15}},  ClassSize{"bowl", {0.06, 0.45, 0.45}},
    ClassSize{"book", {0.06, 0.55, 0.45}},        ClassSize{"clock", {0.06, 0.70, 0.70}},
    ClassSize{"vase", {0.06, 0.90, 0.50}},        ClassSize{"scissors", {0.06, 0.35, 0.15}},
    ClassSize{"teddy bear", {0.08, 1.20, 0.90}},  ClassSize{"backpack", {0.20, 0.80, 0.50}},
    ClassSize{"handbag", {0.15, 0.70, 0.50}},     ClassSize{"suitcase", {0.30, 1.10, 0.80}},
    ClassSize{"chair", {0.35, 1.40, 1.00}},       ClassSize{"sofa", {0.60, 3.50, 2.00}},
    ClassSize{"bed", {1.00, 2.60, 2.30}},         ClassSize{"diningtable", {0.40, 3.50, 2.00}},
    ClassSize{"pottedplant", {0.08, 2.20, 1.60}}, ClassSize{"toilet", {0.40, 1.00, 0.80}},
    ClassSize{"sink", {0.25, 1.50, 0.90}},        ClassSize{"refrigerator", {0.50, 2.20, 1.10}},
    ClassSize{"microwave", {0.30, 0.75, 0.60}},   ClassSize{"oven", {0.40, 1.20, 1.00}},
    ClassSize{"toaster", {0.15, 0.50, 0.35}},     ClassSize{"bench", {0.60, 3.00, 1.00}},
};

}  // namespace

std::optional<SizeRange> SizeRangeOf(const std::string& class_name) {
  const auto it = std::find_if(kSizes.begin(), kSizes.end(), [&](const ClassSize& c) { return c.name == class_name; });
  if (it == kSizes.end()) return std::nullopt;
  return it->range;
}

bool PlausibleSize(const std::string& class_name, const Eigen::Vector3d& dimensions, bool complete) {
  const std::optional<SizeRange> r = SizeRangeOf(class_name);
  if (!r) return true;
  if (dimensions.x() > r->longest_max || dimensions.y() > r->middle_max) return false;
  return !complete || dimensions.x() >= r->longest_min;
}

}  // namespace sgslam
