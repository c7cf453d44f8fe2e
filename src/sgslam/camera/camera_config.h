// The camera: pinhole with radial-tangential distortion, the RGB-D depth encoding
// and the rolling-shutter readout. Defaults: TUM freiburg1 (Kinect), as published
// with the TUM RGB-D benchmark.
#pragma once

#include "sgslam/common/config_checker.h"

namespace sgslam {

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
  // s, rolling-shutter readout, first row to last (rolling_shutter.h); 0: a
  // global shutter. The tum_fr1 preset sets the Kinect's (docs/rolling-shutter.md).
  double readout = 0.0;

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
    v("readout", readout, "s, rolling-shutter readout time, top row to bottom row; 0: global shutter");
  }
  void Validate(ConfigChecker& c) const;
  // m; points closer than this are "close" (ORB-SLAM2's ThDepth).
  double close_depth_m() const { return baseline_fx * close_depth / fx; }
};

}  // namespace sgslam
