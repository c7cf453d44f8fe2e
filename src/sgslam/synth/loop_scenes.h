// Scenes for loop closing and place recognition (presets.h):
//   loop    a hall of 11-12 x 7-7.5 m with textured walls, a poster every ~1.8 m,
//           cabinets along the walls and clutter in the corners. The camera,
//           1.45-1.6 m high, walks a rounded rectangle 1.6 m inside the walls
//           (21-24 m, corner radius 1.2 m) twice, a lap every 30 s (0.7-0.8 m/s),
//           looking 0.9 rad right of its heading and 0.15 rad down, at the walls,
//           so that depth stays within ~0.9-4.5 m. Both laps follow one path; the
//           gaze's slow swing differs between them.
//   repeat  a 3 m wide corridor of five identical 3.3-3.7 m modules (wall, floor and
//           ceiling textures, posters, a box), walked once from the first module's
//           middle to the last's in 20 s, looking 0.95 rad left at one wall: places
//           one module apart look the same, and no place is visited twice.
#pragma once

#include "sgslam/synth/scene.h"

namespace sgslam::synth {

constexpr double kLoopLapSeconds = 30;
constexpr int kLoopLaps = 2;
constexpr int kRepeatModules = 5;
constexpr double kRepeatSeconds = 20;  // first module's middle to the last's

// Default frame counts at 30 Hz: the whole walk, its last pose included.
constexpr int LoopFrames() { return static_cast<int>(kLoopLaps * kLoopLapSeconds * 30) + 1; }
constexpr int RepeatFrames() { return static_cast<int>(kRepeatSeconds * 30) + 1; }

void BuildLoop(Scene& scene);
void BuildRepeat(Scene& scene);

}  // namespace sgslam::synth
