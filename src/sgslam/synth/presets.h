// The named synthetic scenes of `sgslam synth --preset`:
//   static      room, clutter boxes, panels and posters; nothing moves
//   walkers     static + people walking back and forth through the camera's view
//   degenerate  the camera translates along one line with little rotation while a
//               person walks parallel to it (its image motion stays on the
//               epipolar lines, the known blind spot of epipolar checks)
//   objects     static furniture of COCO classes with known boxes, seen while the
//               camera turns round the room
//   rpy         static's room seen from near one spot while the camera rolls,
//               pitches and yaws fast (up to ~1.3 rad/s), like TUM fr1_rpy: for
//               the rolling-shutter model (synth --readout)
//   loop        an 11-12 x 7-7.5 m hall, textured walls, posters and clutter, walked
//               round twice on a closed 21-24 m path (30 s a lap), the camera turned
//               towards the walls: for loop closing (loop_scenes.h)
//   repeat      a corridor of five identical modules (walls, posters, boxes) walked
//               once along: places that look alike 3.3-3.7 m apart, to fool place
//               recognition (loop_scenes.h)
// `static` and `walkers` with the same seed share the room and the camera path.
// loop and repeat default to a Kinect-like depth sensor and a rolling shutter.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sgslam/synth/depth_noise.h"
#include "sgslam/synth/scene.h"

namespace sgslam::synth {

// What `sgslam synth` uses for the options its command line leaves out.
struct PresetDefaults {
  int frames = 300;                            // at 30 Hz
  double readout = 0;                          // s, rolling shutter; 0: global
  DepthNoise depth_noise = DepthNoise::kNone;  // the depth sensor
};

const std::vector<std::string>& PresetNames();

// Throws InputError naming the preset when it is not one of PresetNames().
PresetDefaults DefaultsOf(const std::string& preset);

// Throws InputError naming the preset when it is not one of PresetNames().
Scene BuildScene(const std::string& preset, std::uint32_t seed);

}  // namespace sgslam::synth
