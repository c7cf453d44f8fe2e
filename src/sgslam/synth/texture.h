// Procedural surface textures, evaluated from a hit point's surface coordinates in
// metres, so nothing is stored. A "Mondrian" pattern of rectangles (3-40 cm) on
// three offset grids gives many corners for ORB/FAST at every distance the camera
// sees; a faint 4 mm grain adds texture inside the rectangles.
#pragma once

#include <cstdint>

namespace sgslam::synth {

struct Texture {
  std::uint32_t seed = 0;
  float base_bgr[3] = {0.6f, 0.6f, 0.6f};  // tint, 0..1
  float colourfulness = 0.3f;             // 0: grey levels only, 1: fully saturated random hues
  float min_level = 0.15f;                // darkest rectangle, 0..1
  float max_level = 0.95f;                // brightest rectangle
  float scale = 1.0f;                     // multiplies the rectangle sizes
};

// BGR in 0..255 (before lighting) at surface coordinates (s, r) in metres.
void SampleTexture(const Texture& texture, double s, double r, float bgr[3]);

// Texture presets by surface kind; the seed makes each surface different.
Texture WallTexture(std::uint32_t seed);
Texture FloorTexture(std::uint32_t seed);
Texture CeilingTexture(std::uint32_t seed);
Texture ClutterTexture(std::uint32_t seed);
Texture PersonTexture(std::uint32_t seed);
Texture FurnitureTexture(std::uint32_t seed, float b, float g, float r);

}  // namespace sgslam::synth
