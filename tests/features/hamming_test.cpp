#include "sgslam/features/hamming.h"

#include <gtest/gtest.h>

#include <array>
#include <random>

namespace sgslam::features {
namespace {

int BitByBit(const uint8_t* a, const uint8_t* b) {
  int d = 0;
  for (int byte = 0; byte < 32; ++byte) {
    for (int bit = 0; bit < 8; ++bit) d += ((a[byte] >> bit) & 1) != ((b[byte] >> bit) & 1) ? 1 : 0;
  }
  return d;
}

TEST(Hamming, MatchesBitByBitReferenceOnRandomDescriptors) {
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> byte(0, 255), flips(0, 256);
  // One spare byte so the second descriptor can start at an odd address.
  std::array<uint8_t, 33> a{}, b{};
  for (int trial = 0; trial < 2000; ++trial) {
    for (auto& x : a) x = static_cast<uint8_t>(byte(rng));
    if (trial % 2 == 0) {
      for (auto& x : b) x = static_cast<uint8_t>(byte(rng));
    } else {  // near-duplicates, as real matches are
      b = a;
      const int n = flips(rng) / 8;
      for (int i = 0; i < n; ++i) b[static_cast<size_t>(byte(rng) % 32)] ^= static_cast<uint8_t>(1 << (byte(rng) % 8));
    }
    const int offset = trial % 2;
    ASSERT_EQ(HammingDistance(a.data(), b.data() + offset), BitByBit(a.data(), b.data() + offset)) << trial;
  }
}

TEST(Hamming, Extremes) {
  std::array<uint8_t, 32> zeros{}, ones{};
  ones.fill(0xFF);
  EXPECT_EQ(HammingDistance(zeros.data(), zeros.data()), 0);
  EXPECT_EQ(HammingDistance(zeros.data(), ones.data()), 256);
  std::array<uint8_t, 32> last = zeros;
  last[31] = 0x80;  // the very last bit
  EXPECT_EQ(HammingDistance(zeros.data(), last.data()), 1);
}

}  // namespace
}  // namespace sgslam::features
