// Training a vocabulary tree (vocabulary.h) from the ORB descriptors of a set of
// images: hierarchical k-majority clustering (k-means with Hamming distance and
// bitwise-majority centres, k-means++ seeding), as DBoW2 trains its binary
// vocabularies, then IDF weights from the same images.
//
// Deterministic: equal inputs and seed give an identical tree (and file).
// Thread safety: a free function; `progress` is called on the caller's thread.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include <opencv2/core.hpp>

#include "sgslam/vocab/vocabulary.h"

namespace sgslam::vocab {

struct TrainingOptions {
  int branching = 10;          // k, children per node
  int levels = 5;              // L, depth of the tree (k^L words at most)
  int max_iterations = 10;     // k-majority iterations per node
  std::uint64_t seed = 1;      // of the k-means++ seeding
};

// images: the descriptors (CV_8U, 32 bytes a row) of each training image.
// progress(done, total): clustering work done, in descriptors assigned per level.
// Throws ConfigError for a bad shape, InputError when there are no descriptors.
Vocabulary TrainVocabulary(const std::vector<cv::Mat>& images, const TrainingOptions& options,
                           const std::function<void(std::size_t, std::size_t)>& progress = {});

}  // namespace sgslam::vocab
