#include "sgslam/synth/texture.h"

#include <cmath>

#include "sgslam/synth/random.h"

namespace sgslam::synth {

namespace {

// Rectangle layers: cell size (m), chance a cell holds a rectangle, and the range
// of its side as a fraction of the cell. Smallest side 0.07 * 0.45 = 3 cm, largest
// 0.40 m (a whole coarse cell).
struct Layer {
  double cell;
  float chance;
  float min_fraction, max_fraction;
};
constexpr Layer kLayers[] = {{0.40, 0.7f, 0.35f, 0.9f}, {0.17, 0.35f, 0.3f, 0.85f}, {0.07, 0.15f, 0.45f, 1.0f}};
constexpr double kGrain = 0.004;      // m, cell of the fine grain
constexpr float kGrainAmplitude = 9;  // intensity, peak to peak

// 12 random bits of a hash as a float in [0, 1): five independent fields per hash.
float Unit12(std::uint64_t h, int shift) { return static_cast<float>((h >> shift) & 0xfff) * (1.0f / 4096.0f); }

std::int64_t Cell(double x) { return static_cast<std::int64_t>(std::floor(x)); }

void RectangleColour(const Texture& tex, std::uint64_t h, float bgr[3]) {
  const float level = tex.min_level + (tex.max_level - tex.min_level) * Unit12(h, 36);
  const float hue[3] = {Unit12(h, 0), Unit12(h, 12), Unit12(h, 24)};
  float peak = 1e-3f;
  for (float c : hue) peak = c > peak ? c : peak;
  const float cf = tex.colourfulness;
  for (int k = 0; k < 3; ++k) bgr[k] = 255.f * level * ((1.f - cf) * tex.base_bgr[k] + cf * hue[k] / peak);
}

}  // namespace

void SampleTexture(const Texture& tex, double s, double r, float bgr[3]) {
  const std::uint64_t seed = tex.seed;
  const double inv_scale = 1.0 / tex.scale;
  // Coarse cells always have a colour: the background of the Mondrian. The last
  // rectangle holding the point decides its colour. Branch-free: the rectangles are
  // random, so branches on them would mispredict half of the time.
  const double inv_coarse = inv_scale / kLayers[0].cell;
  std::uint64_t winner = Hash(seed, Cell(s * inv_coarse), Cell(r * inv_coarse), 7);
  for (int l = 0; l < 3; ++l) {
    const Layer& layer = kLayers[l];
    const double inv_cell = inv_scale / layer.cell;
    // Offset grids, and rows shifted like bricks (golden-ratio steps), so edges of
    // the layers rarely line up.
    const double rr = r * inv_cell + 0.37 * l;
    const std::int64_t j = Cell(rr);
    const double ss = s * inv_cell + 0.6180339887 * static_cast<double>(j & 1023) + 0.61 * l;
    const std::int64_t i = Cell(ss);
    const std::uint64_t h = Hash(seed, i, j, l + 1);
    const float span = layer.max_fraction - layer.min_fraction;
    const float w = layer.min_fraction + span * Unit12(h, 0);
    const float hgt = layer.min_fraction + span * Unit12(h, 12);
    const float x0 = (1.f - w) * Unit12(h, 24);
    const float y0 = (1.f - hgt) * Unit12(h, 36);
    const float fx = static_cast<float>(ss - static_cast<double>(i));
    const float fy = static_cast<float>(rr - static_cast<double>(j));
    const bool inside = (Unit12(h, 48) < layer.chance) & (fx >= x0) & (fx < x0 + w) & (fy >= y0) & (fy < y0 + hgt);
    winner = inside ? h : winner;
  }
  RectangleColour(tex, Mix64(winner), bgr);
  constexpr double kInvGrain = 1.0 / kGrain;
  const float grain = kGrainAmplitude * (UnitFloat(Hash(seed, Cell(s * kInvGrain), Cell(r * kInvGrain), 5)) - 0.5f);
  for (int k = 0; k < 3; ++k) bgr[k] += grain;
}

Texture WallTexture(std::uint32_t seed) {
  Texture t;
  t.seed = seed;
  t.base_bgr[0] = 0.86f, t.base_bgr[1] = 0.92f, t.base_bgr[2] = 0.98f;
  t.colourfulness = 0.25f;
  t.min_level = 0.2f, t.max_level = 0.95f;
  return t;
}

Texture FloorTexture(std::uint32_t seed) {
  Texture t;
  t.seed = seed;
  t.base_bgr[0] = 0.55f, t.base_bgr[1] = 0.72f, t.base_bgr[2] = 0.9f;
  t.colourfulness = 0.15f;
  t.min_level = 0.15f, t.max_level = 0.8f;
  return t;
}

Texture CeilingTexture(std::uint32_t seed) {
  Texture t;
  t.seed = seed;
  t.colourfulness = 0.1f;
  t.min_level = 0.45f, t.max_level = 1.0f;
  t.scale = 1.5f;
  return t;
}

Texture ClutterTexture(std::uint32_t seed) {
  Texture t;
  t.seed = seed;
  t.base_bgr[0] = 0.8f, t.base_bgr[1] = 0.75f, t.base_bgr[2] = 0.6f;
  t.colourfulness = 0.45f;
  t.min_level = 0.1f, t.max_level = 0.95f;
  t.scale = 0.7f;
  return t;
}

Texture PersonTexture(std::uint32_t seed) {
  Texture t;
  t.seed = seed;
  t.base_bgr[0] = 0.25f, t.base_bgr[1] = 0.3f, t.base_bgr[2] = 0.95f;  // red clothes, unlike anything else
  t.colourfulness = 0.35f;
  t.min_level = 0.2f, t.max_level = 1.0f;
  t.scale = 0.45f;
  return t;
}

Texture FurnitureTexture(std::uint32_t seed, float b, float g, float r) {
  Texture t;
  t.seed = seed;
  t.base_bgr[0] = b, t.base_bgr[1] = g, t.base_bgr[2] = r;
  t.colourfulness = 0.3f;
  t.min_level = 0.2f, t.max_level = 0.9f;
  t.scale = 0.6f;
  return t;
}

}  // namespace sgslam::synth
