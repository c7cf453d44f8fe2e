#include "sgslam/vocab/training.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <random>
#include <set>

#include "sgslam/common/error.h"
#include "sgslam/features/hamming.h"

namespace sgslam::vocab {

namespace {

using Descriptor = std::array<std::uint8_t, kDescriptorBytes>;

int Distance(const Descriptor& a, const Descriptor& b) { return features::HammingDistance(a.data(), b.data()); }

// Bitwise majority of the members (ties: 0), DBoW2's binary mean.
Descriptor Majority(const std::vector<Descriptor>& all, const std::vector<std::uint32_t>& members) {
  std::array<std::uint32_t, 8 * kDescriptorBytes> ones{};
  for (const std::uint32_t m : members) {
    const Descriptor& d = all[m];
    for (int byte = 0; byte < kDescriptorBytes; ++byte) {
      const std::uint8_t v = d[static_cast<std::size_t>(byte)];
      if (v == 0) continue;
      for (int bit = 0; bit < 8; ++bit) ones[static_cast<std::size_t>(8 * byte + bit)] += (v >> bit) & 1U;
    }
  }
  Descriptor out{};
  for (std::size_t b = 0; b < ones.size(); ++b) {
    if (2 * ones[b] > members.size()) out[b / 8] = static_cast<std::uint8_t>(out[b / 8] | (1U << (b % 8)));
  }
  return out;
}

// k-means++: the first centre at random, each next one drawn with probability
// proportional to the squared distance to the nearest centre chosen so far.
std::vector<Descriptor> SeedCentres(const std::vector<Descriptor>& all, const std::vector<std::uint32_t>& members,
                                    int k, std::mt19937_64& rng) {
  std::vector<Descriptor> centres = {all[members[rng() % members.size()]]};
  std::vector<double> nearest(members.size(), std::numeric_limits<double>::max());
  while (static_cast<int>(centres.size()) < k) {
    double sum = 0;
    for (std::size_t i = 0; i < members.size(); ++i) {
      const double d = Distance(all[members[i]], centres.back());
      nearest[i] = std::min(nearest[i], d * d);
      sum += nearest[i];
    }
    if (sum <= 0) break;  // every member equals a centre: fewer clusters
    double pick = std::uniform_real_distribution<double>(0, sum)(rng);
    std::size_t i = 0;
    while (i + 1 < members.size() && pick >= nearest[i]) pick -= nearest[i++];
    centres.push_back(all[members[i]]);
  }
  return centres;
}

// The members of each cluster, by nearest centre (the first of equals).
std::vector<std::vector<std::uint32_t>> Assign(const std::vector<Descriptor>& all,
                                               const std::vector<std::uint32_t>& members,
                                               const std::vector<Descriptor>& centres) {
  std::vector<std::vector<std::uint32_t>> clusters(centres.size());
  for (const std::uint32_t m : members) {
    std::size_t best = 0;
    int best_distance = std::numeric_limits<int>::max();
    for (std::size_t c = 0; c < centres.size(); ++c) {
      const int d = Distance(all[m], centres[c]);
      if (d < best_distance) best_distance = d, best = c;
    }
    clusters[best].push_back(m);
  }
  return clusters;
}

struct Cluster {
  Descriptor centre;
  std::vector<std::uint32_t> members;
};

// Splits members into at most k clusters. With k members or fewer, each is its own.
std::vector<Cluster> Split(const std::vector<Descriptor>& all, const std::vector<std::uint32_t>& members,
                           const TrainingOptions& options, std::mt19937_64& rng) {
  std::vector<Cluster> out;
  if (static_cast<int>(members.size()) <= options.branching) {
    for (const std::uint32_t m : members) out.push_back({all[m], {m}});
    return out;
  }
  std::vector<Descriptor> centres = SeedCentres(all, members, options.branching, rng);
  std::vector<std::vector<std::uint32_t>> clusters;
  for (int it = 0; it < options.max_iterations; ++it) {
    auto next = Assign(all, members, centres);
    if (next == clusters) break;
    clusters = std::move(next);
    for (std::size_t c = 0; c < centres.size(); ++c) {
      if (!clusters[c].empty()) centres[c] = Majority(all, clusters[c]);
    }
  }
  for (std::size_t c = 0; c < centres.size(); ++c) {
    if (!clusters[c].empty()) out.push_back({centres[c], std::move(clusters[c])});
  }
  return out;
}

void CheckOptions(const TrainingOptions& o) {
  if (o.branching < 2 || o.branching > 64) {
    throw ConfigError("vocabulary branching (--k) must be 2..64, got " + std::to_string(o.branching));
  }
  if (o.levels < 1 || o.levels > 10) {
    throw ConfigError("vocabulary levels (--levels) must be 1..10, got " + std::to_string(o.levels));
  }
  if (std::pow(static_cast<double>(o.branching), o.levels) > 2e7) {
    throw ConfigError("vocabulary of k^L = " + std::to_string(o.branching) + "^" + std::to_string(o.levels) +
                      " words is too large (at most 2e7)");
  }
  if (o.max_iterations < 1) throw ConfigError("vocabulary training needs at least one iteration");
}

// IDF of each word: log(N / n_i), n_i the training images that contain it (at least 1).
void WeighWords(Vocabulary::Node* nodes, std::size_t count, const std::vector<cv::Mat>& images, int branching,
                int levels) {
  const Vocabulary tree(branching, levels, images.size(), std::vector<Vocabulary::Node>(nodes, nodes + count));
  std::vector<std::uint32_t> images_with(tree.size(), 0);
  for (const cv::Mat& d : images) {
    std::set<WordId> seen;
    NodeId unused = 0;
    for (int i = 0; i < d.rows; ++i) seen.insert(tree.Quantize(d.ptr<std::uint8_t>(i), levels, unused));
    for (const WordId w : seen) ++images_with[w];
  }
  for (std::size_t i = 0; i < count; ++i) {
    if (nodes[i].children > 0 || i == 0) continue;
    const WordId w = tree.node(i).word;
    nodes[i].weight = static_cast<float>(
        std::log(static_cast<double>(images.size()) / std::max<std::uint32_t>(1, images_with[w])));
  }
}

}  // namespace

Vocabulary TrainVocabulary(const std::vector<cv::Mat>& images, const TrainingOptions& options,
                           const std::function<void(std::size_t, std::size_t)>& progress) {
  CheckOptions(options);
  std::vector<Descriptor> all;
  for (const cv::Mat& d : images) {
    if (!d.empty() && (d.type() != CV_8U || d.cols != kDescriptorBytes)) {
      throw InputError("vocabulary training: descriptors must be CV_8U rows of 32 bytes");
    }
    for (int i = 0; i < d.rows; ++i) {
      Descriptor x;
      std::copy_n(d.ptr<std::uint8_t>(i), kDescriptorBytes, x.begin());
      all.push_back(x);
    }
  }
  if (all.size() < 2) throw InputError("vocabulary training: fewer than 2 descriptors in the training images");
  std::mt19937_64 rng(options.seed);
  // Breadth-first, so that each node's children are contiguous (the file's order).
  std::vector<Vocabulary::Node> nodes(1);
  std::deque<std::pair<std::size_t, std::vector<std::uint32_t>>> todo;
  std::vector<std::uint32_t> everyone(all.size());
  for (std::uint32_t i = 0; i < everyone.size(); ++i) everyone[i] = i;
  todo.emplace_back(0, std::move(everyone));
  const std::size_t total = all.size() * static_cast<std::size_t>(options.levels);
  std::size_t done = 0;
  while (!todo.empty()) {
    auto [parent, members] = std::move(todo.front());
    todo.pop_front();
    const int level = nodes[parent].level;
    std::vector<Cluster> clusters = Split(all, members, options, rng);
    nodes[parent].children = static_cast<std::uint16_t>(clusters.size());
    for (Cluster& c : clusters) {
      Vocabulary::Node n;
      n.descriptor = c.centre;
      n.level = static_cast<std::uint16_t>(level + 1);
      nodes.push_back(n);
      if (level + 1 < options.levels && c.members.size() > 1) todo.emplace_back(nodes.size() - 1, std::move(c.members));
    }
    done += members.size();
    if (progress) progress(std::min(done, total), total);
  }
  WeighWords(nodes.data(), nodes.size(), images, options.branching, options.levels);
  return Vocabulary(options.branching, options.levels, images.size(), std::move(nodes));
}

}  // namespace sgslam::vocab
