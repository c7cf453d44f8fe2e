// A vocabulary tree over 256-bit ORB descriptors (Galvez-Lopez and Tardos, "Bags
// of binary words", 2012; DBoW2): a tree of branching k and depth L whose nodes
// are descriptors (the bitwise majority of their cluster), whose leaves are the
// words, each with an IDF weight log(N / n_i) from the N training images, n_i of
// which contain it. An image's descriptors descend to their nearest child at
// every level; the leaves they reach, weighted by TF-IDF and L1-normalised, are
// its bag of words (bow_vector.h).
//
// File (little-endian, version 1): "SGVOCAB\0", u32 version, u32 k, u32 L,
// u32 node count, u64 training images; then every node in breadth-first order,
// children of a node contiguous, the root first: u16 children, 32 descriptor
// bytes, f32 weight (leaves: IDF; inner nodes: 0); then the SHA-256 of all the
// bytes before it as 64 hex digits. A file whose size, magic, version, shape or
// checksum is wrong is refused with an InputError naming the file.
//
// Thread safety: immutable once loaded or trained; Transform is const and may be
// called from any thread.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <opencv2/core.hpp>

#include "sgslam/vocab/bow_vector.h"

namespace sgslam::vocab {

constexpr std::uint32_t kVocabularyVersion = 1;
inline constexpr std::string_view kFileMagic{"SGVOCAB\0", 8};  // the first bytes of every vocabulary file
constexpr int kDescriptorBytes = 32;

class Vocabulary {
 public:
  struct Node {
    std::array<std::uint8_t, kDescriptorBytes> descriptor{};
    std::uint32_t first_child = 0;  // index of the first child; children are contiguous
    std::uint16_t children = 0;     // 0: a leaf (a word)
    std::uint16_t level = 0;        // root 0, its children 1, ..., leaves <= L
    float weight = 0;               // IDF of a word; 0 for inner nodes
    WordId word = 0;                // leaves: index among the words
  };

  Vocabulary() = default;
  // nodes: breadth-first, the root first, each node's children contiguous (the
  // file order). Throws InputError naming `what` when the tree is inconsistent or a
  // word's weight is not an IDF (in [0, log training_images]).
  Vocabulary(int branching, int levels, std::uint64_t training_images, std::vector<Node> nodes,
             const std::string& what = "vocabulary");

  static Vocabulary Load(const std::filesystem::path& file);
  // Written atomically (a temporary file renamed over `file`).
  void Save(const std::filesystem::path& file) const;

  bool empty() const { return nodes_.empty(); }
  int branching() const { return branching_; }
  int levels() const { return levels_; }
  std::size_t size() const { return words_.size(); }  // number of words
  std::size_t nodes() const { return nodes_.size(); }
  std::uint64_t training_images() const { return training_images_; }
  const Node& node(std::size_t i) const { return nodes_[i]; }
  float weight(WordId w) const { return nodes_[words_[w]].weight; }

  // The word (leaf) one descriptor (32 bytes) falls into, and the node at
  // `node_level` on its way (the leaf itself if the branch ends above it).
  WordId Quantize(const std::uint8_t* descriptor, int node_level, NodeId& node) const;
  // The bag of words of an image's descriptors (CV_8U, 32 bytes a row), and its
  // direct index at `levels_up` levels above the leaves (ORB-SLAM2: 4 of 6).
  BowData Transform(const cv::Mat& descriptors, int levels_up) const;
  // The SHA-256 of the file contents (hex): names the vocabulary in stats.
  const std::string& checksum() const { return checksum_; }

  // The serialised file contents (what Save writes).
  std::string Serialize() const { return SerializeBody() + checksum_; }

 private:
  std::string SerializeBody() const;

  int branching_ = 0, levels_ = 0;
  std::uint64_t training_images_ = 0;
  std::vector<Node> nodes_;
  std::vector<NodeId> words_;  // word -> node index
  std::string checksum_;
};

}  // namespace sgslam::vocab
