// Bag-of-words vectors of an image (DBoW2's BowVector and FeatureVector): the
// words its descriptors fall into, weighted by TF-IDF and L1-normalised, and for
// each node of one tree level the keypoints below it (the "direct index", which
// restricts descriptor matching between two images to keypoints under the same
// node).
//
// Both are sorted by id, so two vectors are compared by one merge walk.
#pragma once

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

namespace sgslam::vocab {

using WordId = std::uint32_t;
using NodeId = std::uint32_t;

// (word, weight), ids ascending, weights summing to 1 (empty for no descriptors).
using BowVector = std::vector<std::pair<WordId, float>>;
// (node, keypoint indices ascending), node ids ascending.
using FeatureVector = std::vector<std::pair<NodeId, std::vector<std::uint32_t>>>;

struct BowData {
  BowVector words;
  FeatureVector nodes;
};

// Calls fn(x, y) for each entry x of a and y of b with the same id (both sorted by
// id): the shared words of two bags, the shared nodes of two direct indexes.
template <typename A, typename B, typename Fn>
void ForEachShared(const A& a, const B& b, Fn fn) {
  auto i = a.begin();
  auto j = b.begin();
  while (i != a.end() && j != b.end()) {
    if (i->first < j->first) {
      ++i;
    } else if (j->first < i->first) {
      ++j;
    } else {
      fn(*i, *j);
      ++i, ++j;
    }
  }
}

// DBoW2's L1 score of two L1-normalised vectors, 1 - |a - b|_1 / 2: 1 for equal
// vectors, 0 for vectors without a common word.
inline double Score(const BowVector& a, const BowVector& b) {
  double s = 0;
  // Each shared word adds (|x| + |y| - |x - y|) / 2.
  ForEachShared(a, b, [&](const auto& x, const auto& y) { s += std::min(x.second, y.second); });
  return s;
}

}  // namespace sgslam::vocab
