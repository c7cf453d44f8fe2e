// The vocabulary tree: quantisation, bag-of-words scores, training, and the file.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <random>

#include "sgslam/common/data_dir.h"
#include "sgslam/common/error.h"
#include "sgslam/common/sha256.h"
#include "sgslam/features/hamming.h"
#include "sgslam/loop/vocabulary_file.h"
#include "sgslam/vocab/training.h"
#include "support/test_support.h"

namespace sgslam::vocab {
namespace {

// n "images" of descriptors drawn around `centres` random centres (each bit
// flipped with probability noise), the same centres for every image.
std::vector<cv::Mat> ClusteredImages(int images, int per_image, int centres, double noise, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<std::array<std::uint8_t, 32>> c(static_cast<std::size_t>(centres));
  for (auto& x : c) for (auto& b : x) b = static_cast<std::uint8_t>(rng());
  std::bernoulli_distribution flip(noise);
  std::vector<cv::Mat> out;
  for (int i = 0; i < images; ++i) {
    cv::Mat d(per_image, 32, CV_8U);
    for (int r = 0; r < per_image; ++r) {
      const auto& base = c[rng() % c.size()];
      for (int b = 0; b < 32; ++b) {
        std::uint8_t v = base[static_cast<std::size_t>(b)];
        for (int bit = 0; bit < 8; ++bit) if (flip(rng)) v = static_cast<std::uint8_t>(v ^ (1U << bit));
        d.at<std::uint8_t>(r, b) = v;
      }
    }
    out.push_back(d);
  }
  return out;
}

Vocabulary SmallVocabulary(std::uint64_t seed = 1) {
  TrainingOptions o;
  o.branching = 4;
  o.levels = 3;
  o.seed = seed;
  return TrainVocabulary(ClusteredImages(20, 200, 40, 0.05, 7), o);
}

TEST(Vocabulary, EveryStepOfTheDescentTakesTheNearestChild) {
  const Vocabulary v = SmallVocabulary();
  const cv::Mat probe = ClusteredImages(1, 100, 40, 0.1, 99)[0];
  for (int r = 0; r < probe.rows; ++r) {
    const std::uint8_t* d = probe.ptr<std::uint8_t>(r);
    std::size_t at = 0;
    while (v.node(at).children > 0) {
      const auto& n = v.node(at);
      std::size_t best = n.first_child;
      for (std::size_t c = n.first_child; c < n.first_child + n.children; ++c) {
        if (features::HammingDistance(d, v.node(c).descriptor.data()) <
            features::HammingDistance(d, v.node(best).descriptor.data())) best = c;
      }
      at = best;
    }
    NodeId node = 0;
    EXPECT_EQ(v.Quantize(d, v.levels(), node), v.node(at).word);
  }
}

TEST(Vocabulary, ScoresOfIdenticalImagesAreOneAndOfUnrelatedNearZero) {
  const Vocabulary v = SmallVocabulary();
  const auto images = ClusteredImages(2, 300, 40, 0.05, 7);
  const BowVector a = v.Transform(images[0], 1).words;
  EXPECT_NEAR(Score(a, a), 1.0, 1e-6);
  double sum = 0;
  for (const auto& [w, x] : a) sum += x;
  EXPECT_NEAR(sum, 1.0, 1e-5);
  cv::Mat random(300, 32, CV_8U);
  cv::randu(random, 0, 256);
  const BowVector b = v.Transform(random, 1).words;
  EXPECT_LT(Score(a, b), Score(a, v.Transform(images[1], 1).words));
  EXPECT_NEAR(Score(a, b), Score(b, a), 1e-9);
  EXPECT_EQ(Score(a, {}), 0.0);
}

TEST(Vocabulary, DirectIndexHoldsEveryKeypointOnce) {
  const Vocabulary v = SmallVocabulary();
  const cv::Mat d = ClusteredImages(1, 250, 40, 0.05, 3)[0];
  const BowData bow = v.Transform(d, 1);
  std::vector<int> seen(250, 0);
  for (const auto& [node, keys] : bow.nodes) {
    EXPECT_LE(v.node(node).level, v.levels() - 1);
    for (const auto k : keys) ++seen[k];
  }
  for (int s : seen) EXPECT_EQ(s, 1);
}

TEST(Vocabulary, TrainingIsDeterministic) {
  EXPECT_EQ(SmallVocabulary(5).checksum(), SmallVocabulary(5).checksum());
  EXPECT_NE(SmallVocabulary(5).checksum(), SmallVocabulary(6).checksum());
}

TEST(Vocabulary, FileRoundTrip) {
  const test::TempDir dir;
  const Vocabulary v = SmallVocabulary();
  v.Save(dir / "v.vocab");
  const Vocabulary w = Vocabulary::Load(dir / "v.vocab");
  EXPECT_EQ(w.checksum(), v.checksum());
  EXPECT_EQ(w.size(), v.size());
  const cv::Mat d = ClusteredImages(1, 100, 40, 0.1, 11)[0];
  EXPECT_EQ(w.Transform(d, 1).words, v.Transform(d, 1).words);
}

// Loading `bytes` fails with an error naming the file and containing `what`.
void ExpectRefused(const std::string& bytes, const std::string& what) {
  const test::TempDir dir;
  const auto file = dir / "bad.vocab";
  std::ofstream(file, std::ios::binary) << bytes;
  try {
    Vocabulary::Load(file);
    FAIL() << "loaded a broken vocabulary (" << what << ")";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
  }
}

TEST(Vocabulary, BrokenFilesAreRefusedNamingTheFile) {
  const std::string good = SmallVocabulary().Serialize();
  ExpectRefused(good.substr(0, good.size() / 2), "truncated");
  std::string flipped = good;
  flipped[good.size() / 2] = static_cast<char>(flipped[good.size() / 2] ^ 1);
  ExpectRefused(flipped, "checksum");
  std::string version = good;
  version[8] = 7;
  ExpectRefused(version, "version 7");
  ExpectRefused("hello, world, this is not a vocabulary at all, not even close to one, no", "not an sgslam vocabulary");
  ExpectRefused("", "not an sgslam vocabulary");
  EXPECT_THROW(Vocabulary::Load("/nonexistent/v.vocab"), InputError);
}

// A word weight far above any IDF loaded, and a few descriptors that fell into it
// added up past float's range in Transform: NaN scores (found by the vocabulary
// fuzz target).
TEST(Vocabulary, AWeightAboveAnyIdfIsRefused) {
  const std::string good = SmallVocabulary().Serialize();
  std::string body = good.substr(0, good.size() - 64);
  const float weight = 9e37f;  // the last node, a leaf
  std::memcpy(body.data() + body.size() - sizeof weight, &weight, sizeof weight);
  ExpectRefused(body + Sha256Hex(body), "has the weight 9e+37, outside an IDF's range");
}

TEST(Vocabulary, BadTrainingOptionsAreRefused) {
  TrainingOptions o;
  o.branching = 1;
  EXPECT_THROW(TrainVocabulary(ClusteredImages(2, 10, 3, 0.1, 1), o), ConfigError);
  EXPECT_THROW(TrainVocabulary({}, TrainingOptions{}), InputError);
}

TEST(Vocabulary, TheShippedVocabularyLoads) {
  const auto file = ResolveVocabulary("");
  const Vocabulary v = Vocabulary::Load(file);
  EXPECT_EQ(v.branching(), 10);
  EXPECT_EQ(v.levels(), 5);
  EXPECT_GT(v.size(), 10000U);
}

TEST(Vocabulary, AMissingConfiguredVocabularyIsNamed) {
  try {
    ResolveVocabulary("/nonexistent/my.vocab");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/my.vocab"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("loop.enabled"), std::string::npos);
  }
}

}  // namespace
}  // namespace sgslam::vocab
