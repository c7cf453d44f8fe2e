// Hamming distance between two 256-bit ORB descriptors: the inner loop of
// every matcher, so four 64-bit words and POPCNT (-march=x86-64-v2) instead of
// a byte table. The descriptors need no alignment.
#pragma once

#include <cstdint>
#include <cstring>

namespace sgslam::features {

// a, b: 32 bytes each (one row of a CV_8U descriptor matrix). Returns 0..256.
inline int HammingDistance(const uint8_t* a, const uint8_t* b) {
  int d = 0;
  for (int w = 0; w < 4; ++w) {
    uint64_t x, y;
    std::memcpy(&x, a + 8 * w, 8);  // memcpy: rows of a cv::Mat need not be 8-byte aligned
    std::memcpy(&y, b + 8 * w, 8);
    d += __builtin_popcountll(x ^ y);
  }
  return d;
}

}  // namespace sgslam::features
