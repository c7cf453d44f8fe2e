#include "sgslam/vocab/vocabulary.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <limits>
#include <map>

#include "sgslam/common/error.h"
#include "sgslam/common/regular_file.h"
#include "sgslam/common/sha256.h"
#include "sgslam/features/hamming.h"
#include "sgslam/io/atomic_write.h"

namespace sgslam::vocab {

static_assert(std::endian::native == std::endian::little, "the vocabulary file is read and written little-endian");

namespace {

constexpr std::size_t kHeaderBytes = kFileMagic.size() + 4 * 4 + 8;
constexpr std::size_t kNodeBytes = 2 + kDescriptorBytes + 4;
constexpr std::size_t kChecksumChars = 64;
constexpr int kMaxBranching = 64;
constexpr int kMaxLevels = 10;

template <typename T>
void Put(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.append(bytes, sizeof(T));
}

// Reads a T at `offset` of `in`; the caller has checked the size.
template <typename T>
T Get(const std::string& in, std::size_t& offset) {
  T value;
  std::memcpy(&value, in.data() + offset, sizeof(T));
  offset += sizeof(T);
  return value;
}

}  // namespace

Vocabulary::Vocabulary(int branching, int levels, std::uint64_t training_images, std::vector<Node> nodes,
                       const std::string& what)
    : branching_(branching), levels_(levels), training_images_(training_images), nodes_(std::move(nodes)) {
  if (branching_ < 2 || branching_ > kMaxBranching || levels_ < 1 || levels_ > kMaxLevels) {
    throw InputError(what + ": branching " + std::to_string(branching_) + " and levels " + std::to_string(levels_) +
                     " are out of range (2.." + std::to_string(kMaxBranching) + ", 1.." + std::to_string(kMaxLevels) +
                     ")");
  }
  if (nodes_.empty()) throw InputError(what + ": no nodes");
  // A word's IDF log(N / n_i) is at most log N (float's rounding aside); a larger
  // weight is no trained vocabulary's, and a few of them add up past float's range
  // in Transform.
  const double max_weight = std::log(static_cast<double>(std::max<std::uint64_t>(training_images_, 1))) * (1 + 1e-6);
  // Breadth-first: the children of node i follow those of node i - 1.
  std::size_t next = 1;
  nodes_[0].level = 0;
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    if (i > 0 && i >= next) throw InputError(what + ": node " + std::to_string(i) + " has no parent");
    Node& n = nodes_[i];
    if (n.children > branching_ || (n.children > 0 && n.level >= levels_)) {
      throw InputError(what + ": node " + std::to_string(i) + " has " + std::to_string(n.children) +
                       " children at level " + std::to_string(n.level) + " (branching " + std::to_string(branching_) +
                       ", levels " + std::to_string(levels_) + ")");
    }
    if (next + n.children > nodes_.size()) throw InputError(what + ": the tree's node count is inconsistent");
    n.first_child = static_cast<std::uint32_t>(next);
    for (std::size_t c = next; c < next + n.children; ++c) nodes_[c].level = static_cast<std::uint16_t>(n.level + 1);
    next += n.children;
    if (n.children == 0 && i > 0) {
      if (!(n.weight >= 0 && n.weight <= max_weight)) {
        char weight[32];
        std::snprintf(weight, sizeof weight, "%g", static_cast<double>(n.weight));
        throw InputError(what + ": node " + std::to_string(i) + " has the weight " + weight +
                         ", outside an IDF's range [0, log(" + std::to_string(training_images_) + " training images)]");
      }
      n.word = static_cast<WordId>(words_.size());
      words_.push_back(static_cast<NodeId>(i));
    }
  }
  if (next != nodes_.size()) throw InputError(what + ": the tree's node count is inconsistent");
  if (words_.empty()) throw InputError(what + ": no words");
  checksum_ = Sha256Hex(SerializeBody());
}

std::string Vocabulary::SerializeBody() const {
  std::string out;
  out.reserve(kHeaderBytes + nodes_.size() * kNodeBytes + kChecksumChars);
  out.append(kFileMagic);
  Put<std::uint32_t>(out, kVocabularyVersion);
  Put<std::uint32_t>(out, static_cast<std::uint32_t>(branching_));
  Put<std::uint32_t>(out, static_cast<std::uint32_t>(levels_));
  Put<std::uint32_t>(out, static_cast<std::uint32_t>(nodes_.size()));
  Put<std::uint64_t>(out, training_images_);
  for (const Node& n : nodes_) {
    Put<std::uint16_t>(out, n.children);
    out.append(reinterpret_cast<const char*>(n.descriptor.data()), kDescriptorBytes);
    Put<float>(out, n.weight);
  }
  return out;
}

void Vocabulary::Save(const std::filesystem::path& file) const { WriteFileAtomically(file, Serialize()); }

namespace {

// Nodes a file may hold: 16 times the 4.2 million of a k 10, L 7 tree as far as
// DBoW2's largest; 2.5 GB of file. A header claiming more is the wrong file.
constexpr std::uint64_t kMaxNodes = std::uint64_t{1} << 26;

struct Header {
  std::uint32_t branching = 0, levels = 0, count = 0;
  std::uint64_t images = 0;
};

// The header, checked before the body is read: magic, version, shape, and the
// file's size against the node count it gives.
Header ReadHeader(const RegularFile& file, const std::string& what) {
  if (file.size() < kHeaderBytes + kChecksumChars) {
    throw InputError(what + ": not an sgslam vocabulary file (" + std::to_string(file.size()) +
                     " bytes, too short for one; train one with `sgslam vocab train`)");
  }
  const std::string bytes = file.Read(0, kHeaderBytes);
  if (bytes.compare(0, kFileMagic.size(), kFileMagic) != 0) {
    throw InputError(what + ": not an sgslam vocabulary file (no SGVOCAB header; train one with `sgslam vocab train`)");
  }
  std::size_t at = kFileMagic.size();
  if (const auto version = Get<std::uint32_t>(bytes, at); version != kVocabularyVersion) {
    throw InputError(what + ": file version " + std::to_string(version) + ", this build reads version " +
                     std::to_string(kVocabularyVersion) + " (train it again with `sgslam vocab train`)");
  }
  Header h;
  h.branching = Get<std::uint32_t>(bytes, at);
  h.levels = Get<std::uint32_t>(bytes, at);
  h.count = Get<std::uint32_t>(bytes, at);
  h.images = Get<std::uint64_t>(bytes, at);
  if (h.branching > kMaxBranching || h.levels > kMaxLevels || h.count > kMaxNodes) {
    throw InputError(what + ": branching " + std::to_string(h.branching) + ", levels " + std::to_string(h.levels) +
                     " or node count " + std::to_string(h.count) + " out of range (corrupt header)");
  }
  const std::uint64_t expected = kHeaderBytes + std::uint64_t{h.count} * kNodeBytes + kChecksumChars;
  if (file.size() != expected) {
    throw InputError(what + ": " + std::to_string(file.size()) + " bytes, expected " + std::to_string(expected) +
                     " for the " + std::to_string(h.count) + " nodes its header gives (truncated or corrupt)");
  }
  return h;
}

}  // namespace

Vocabulary Vocabulary::Load(const std::filesystem::path& file) {
  const std::string what = "vocabulary " + file.string();
  const RegularFile in(file, "vocabulary");
  const Header h = ReadHeader(in, what);
  // The checksum before the body is held: a header that fits the file's size says
  // nothing of what follows it.
  const std::uint64_t body = in.size() - kChecksumChars;
  if (Sha256HexOfFile(in, 0, body) != in.Read(body, kChecksumChars)) {
    throw InputError(what + ": checksum mismatch (the file is corrupt)");
  }
  const std::string bytes = in.Read(0, static_cast<std::size_t>(body));
  std::vector<Node> nodes(h.count);
  std::size_t at = kHeaderBytes;
  for (Node& n : nodes) {
    n.children = Get<std::uint16_t>(bytes, at);
    std::memcpy(n.descriptor.data(), bytes.data() + at, kDescriptorBytes);
    at += kDescriptorBytes;
    n.weight = Get<float>(bytes, at);
  }
  return Vocabulary(static_cast<int>(h.branching), static_cast<int>(h.levels), h.images, std::move(nodes), what);
}

WordId Vocabulary::Quantize(const std::uint8_t* descriptor, int node_level, NodeId& node) const {
  std::size_t at = 0;
  node = 0;
  while (nodes_[at].children > 0) {
    const Node& n = nodes_[at];
    std::size_t best = n.first_child;
    int best_distance = std::numeric_limits<int>::max();
    for (std::size_t c = n.first_child; c < n.first_child + n.children; ++c) {
      const int d = features::HammingDistance(descriptor, nodes_[c].descriptor.data());
      if (d < best_distance) best_distance = d, best = c;
    }
    at = best;
    if (nodes_[at].level <= node_level) node = static_cast<NodeId>(at);
  }
  return nodes_[at].word;
}

BowData Vocabulary::Transform(const cv::Mat& descriptors, int levels_up) const {
  BowData out;
  if (descriptors.empty() || nodes_.empty()) return out;
  const int node_level = std::max(1, levels_ - levels_up);
  std::map<WordId, float> words;
  std::map<NodeId, std::vector<std::uint32_t>> nodes;
  for (int i = 0; i < descriptors.rows; ++i) {
    NodeId node = 0;
    const WordId w = Quantize(descriptors.ptr<std::uint8_t>(i), node_level, node);
    const float weight = nodes_[words_[w]].weight;
    if (weight > 0) words[w] += weight;  // TF-IDF: the TF's 1/n cancels in the normalisation
    nodes[node].push_back(static_cast<std::uint32_t>(i));
  }
  double sum = 0;
  for (const auto& [w, v] : words) sum += v;
  out.words.reserve(words.size());
  for (const auto& [w, v] : words) out.words.emplace_back(w, static_cast<float>(v / sum));
  out.nodes.assign(std::make_move_iterator(nodes.begin()), std::make_move_iterator(nodes.end()));
  return out;
}

}  // namespace sgslam::vocab
