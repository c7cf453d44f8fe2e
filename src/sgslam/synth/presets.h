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
// `static` and `walkers` with the same seed share the room and the camera path.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sgslam/synth/scene.h"

namespace sgslam::synth {

const std::vector<std::string>& PresetNames();

// Throws InputError naming the preset when it is not one of PresetNames().
Scene BuildScene(const std::string& preset, std::uint32_t seed);

}  // namespace sgslam::synth
