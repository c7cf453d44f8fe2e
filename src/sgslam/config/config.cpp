#include "sgslam/config/config.h"

#include <cmath>

#include "sgslam/common/error.h"

namespace sgslam {

void CameraConfig::Validate(ConfigChecker& c) const {
  c.InRange("width", width, 16, 8192);
  c.InRange("height", height, 16, 8192);
  c.Positive("fx", fx);
  c.Positive("fy", fy);
  c.InRange("cx", cx, 0.0, static_cast<double>(width));
  c.InRange("cy", cy, 0.0, static_cast<double>(height));
  for (const auto& [key, value] : {std::pair{"k1", k1}, {"k2", k2}, {"p1", p1}, {"p2", p2}, {"k3", k3}}) {
    c.Check(std::isfinite(value) && std::abs(value) < 100.0, key, value, "must be a finite distortion coefficient");
  }
  c.InRange("fps", fps, 0.1, 1000.0);
  c.Positive("depth_factor", depth_factor);
  c.Positive("baseline_fx", baseline_fx);
  c.Positive("close_depth", close_depth);
}

void DatasetConfig::Validate(ConfigChecker& c) const {
  c.InRange("max_time_difference", max_time_difference, 1e-6, 1.0);
  c.InRange("prefetch", prefetch, 1, 64);
  c.Positive("min_median_depth", min_median_depth);
  c.Check(max_median_depth > min_median_depth, "max_median_depth", max_median_depth, "must be > min_median_depth");
}

void OrbConfig::Validate(ConfigChecker& c) const {
  c.InRange("features", features, 50, 20000);
  c.InRange("scale_factor", scale_factor, 1.01, 2.0);
  c.InRange("levels", levels, 1, 16);
  c.InRange("fast_threshold", fast_threshold, 1, 254);
  c.InRange("fast_min_threshold", fast_min_threshold, 1, 254);
  c.Check(fast_min_threshold <= fast_threshold, "fast_min_threshold", fast_min_threshold, "must be <= fast_threshold");
  c.InRange("cell_size", cell_size, 10, 200);
}

void Config::Validate(const std::string& source) const {
  ConfigChecker checker("");
  VisitSections([&](const char* name, const auto& section) {
    checker.SetSection(name);
    section.Validate(checker);
  });
  if (checker.problems().empty()) return;
  std::string message = "invalid configuration (" + source + "):";
  for (const auto& p : checker.problems()) message += "\n  " + p;
  throw ConfigError(message);
}

}  // namespace sgslam
