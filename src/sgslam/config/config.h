// Configuration: one plain struct per module with in-class defaults and the unit of
// each field in its comment. Each struct lists its fields once in Visit(), which
// the YAML loader, the printer and the unknown-key check all use, and checks its
// values in Validate(), which runs before any thread starts.
#pragma once

#include <string>

#include "sgslam/config/checker.h"

namespace sgslam {

// Pinhole camera with radial-tangential distortion, and the RGB-D depth encoding.
// Defaults: TUM freiburg1 (Kinect), as published with the TUM RGB-D benchmark.
struct CameraConfig {
  int width = 640;               // px
  int height = 480;              // px
  double fx = 517.306408;        // px
  double fy = 516.469215;        // px
  double cx = 318.643040;        // px
  double cy = 255.313989;        // px
  double k1 = 0.262383;          // radial distortion (OpenCV model)
  double k2 = -0.953104;         // radial distortion
  double p1 = -0.005358;         // tangential distortion
  double p2 = 0.002628;          // tangential distortion
  double k3 = 1.163314;          // radial distortion
  double fps = 30.0;             // Hz, frame rate of the sensor
  double depth_factor = 5000.0;  // raw depth units per metre (TUM and Bonn: 5000)
  double baseline_fx = 40.0;     // px*m, virtual stereo baseline times fx (ORB-SLAM2 "bf"), for u_r = u - bf/d
  double close_depth = 40.0;     // baselines; points closer than close_depth * bf / fx are "close" (ThDepth)

  template <class V>
  void Visit(V&& v) {
    v("width", width, "px");
    v("height", height, "px");
    v("fx", fx, "px");
    v("fy", fy, "px");
    v("cx", cx, "px");
    v("cy", cy, "px");
    v("k1", k1, "radial distortion");
    v("k2", k2, "radial distortion");
    v("p1", p1, "tangential distortion");
    v("p2", p2, "tangential distortion");
    v("k3", k3, "radial distortion");
    v("fps", fps, "Hz");
    v("depth_factor", depth_factor, "raw depth units per metre");
    v("baseline_fx", baseline_fx, "px*m, virtual stereo baseline times fx");
    v("close_depth", close_depth, "baselines, near/far limit of depth points");
  }
  void Validate(ConfigChecker& c) const;
};

// Reading datasets.
struct DatasetConfig {
  double max_time_difference = 0.02;  // s, RGB-depth association window (TUM associate.py default)
  int prefetch = 3;                   // frames read ahead of the consumer
  double min_median_depth = 0.1;      // m, a first frame whose median depth is below: wrong depth_factor
  double max_median_depth = 20.0;     // m, ... above: wrong depth_factor

  template <class V>
  void Visit(V&& v) {
    v("max_time_difference", max_time_difference, "s, RGB-depth association window");
    v("prefetch", prefetch, "frames read ahead");
    v("min_median_depth", min_median_depth, "m, depth-scale sanity check");
    v("max_median_depth", max_median_depth, "m, depth-scale sanity check");
  }
  void Validate(ConfigChecker& c) const;
};

// ORB features (ORB-SLAM2's settings for 640x480 RGB-D).
struct OrbConfig {
  int features = 1000;           // keypoints per frame, spread over levels and image cells
  double scale_factor = 1.2;     // ratio between pyramid levels
  int levels = 8;                // pyramid levels
  int fast_threshold = 20;       // intensity, FAST threshold tried first in each cell
  int fast_min_threshold = 7;    // intensity, fallback for cells where the first finds nothing
  int cell_size = 35;            // px, FAST is run per cell of this size

  template <class V>
  void Visit(V&& v) {
    v("features", features, "keypoints per frame");
    v("scale_factor", scale_factor, "ratio between pyramid levels");
    v("levels", levels, "pyramid levels");
    v("fast_threshold", fast_threshold, "intensity, FAST threshold");
    v("fast_min_threshold", fast_min_threshold, "intensity, FAST fallback threshold");
    v("cell_size", cell_size, "px, FAST cell size");
  }
  void Validate(ConfigChecker& c) const;
};

struct Config {
  CameraConfig camera;
  DatasetConfig dataset;
  OrbConfig orb;

  template <class V>
  void VisitSections(V&& v) {
    v("camera", camera);
    v("dataset", dataset);
    v("orb", orb);
  }
  template <class V>
  void VisitSections(V&& v) const {
    const_cast<Config*>(this)->VisitSections(v);  // the visitors never write through const
  }

  // Throws ConfigError naming `source` and every bad key with its value.
  void Validate(const std::string& source) const;
};

}  // namespace sgslam
