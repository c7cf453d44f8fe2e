// Portable deterministic randomness for the synthetic scenes: the standard
// distributions differ between standard libraries, so same seed -> same bytes
// needs our own. SplitMix64 (Steele et al. 2014) for both streams and hashes.
#pragma once

#include <cstdint>

namespace sgslam::synth {

inline std::uint64_t Mix64(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// Hash of a seed and up to three integer coordinates (texture cells, pixels).
// One mix only: it runs several times per pixel; good enough for textures and noise.
inline std::uint64_t Hash(std::uint64_t seed, std::int64_t a, std::int64_t b = 0, std::int64_t c = 0) {
  return Mix64(seed * 0x2545f4914f6cdd1dULL + static_cast<std::uint64_t>(a) * 0x9e3779b97f4a7c15ULL +
               static_cast<std::uint64_t>(b) * 0xd1b54a32d192ed03ULL + static_cast<std::uint64_t>(c) * 0xaef17502108ef2d9ULL);
}

// Uniform in [0, 1) from the top 24 bits of a hash, or from bits [shift, shift + 24).
inline float UnitFloat(std::uint64_t h, int shift = 40) {
  return static_cast<float>((h >> shift) & 0xffffff) * (1.0f / 16777216.0f);
}

class Rng {
 public:
  explicit Rng(std::uint64_t seed) : state_(seed) {}
  std::uint64_t Next() {
    state_ += 0x9e3779b97f4a7c15ULL;
    return Mix64(state_);
  }
  double Uniform(double lo, double hi) {
    return lo + (hi - lo) * static_cast<double>(Next() >> 11) * (1.0 / 9007199254740992.0);
  }
  int UniformInt(int lo, int hi) {  // inclusive
    return lo + static_cast<int>(Next() % static_cast<std::uint64_t>(hi - lo + 1));
  }
  double Sign() { return (Next() & 1) ? 1.0 : -1.0; }
  std::uint32_t Seed() { return static_cast<std::uint32_t>(Next() >> 32); }

 private:
  std::uint64_t state_;
};

}  // namespace sgslam::synth
