// The place-recognition database: candidates for relocalisation and loops.
#include "sgslam/loop/keyframe_database.h"

#include <gtest/gtest.h>

#include <random>

#include "sgslam/map/map.h"
#include "sgslam/vocab/training.h"

namespace sgslam {
namespace {

// Random descriptors for `places` places; each keyframe of a place sees a noisy
// copy of the place's descriptors.
class Places {
 public:
  explicit Places(int places) : rng_(3) {
    for (int p = 0; p < places; ++p) {
      cv::Mat d(300, 32, CV_8U);
      cv::randu(d, 0, 256);
      place_.push_back(d);
    }
    std::vector<cv::Mat> training;
    for (int p = 0; p < places; ++p) training.push_back(View(p));
    vocab::TrainingOptions o;
    o.branching = 8;
    o.levels = 4;
    vocabulary_ = std::make_shared<const vocab::Vocabulary>(vocab::TrainVocabulary(training, o));
  }

  cv::Mat View(int p) {
    cv::Mat d = place_[static_cast<std::size_t>(p)].clone();
    std::bernoulli_distribution flip(0.03);
    for (int r = 0; r < d.rows; ++r) {
      for (int b = 0; b < 32; ++b) {
        for (int bit = 0; bit < 8; ++bit) {
          if (flip(rng_)) d.at<std::uint8_t>(r, b) = static_cast<std::uint8_t>(d.at<std::uint8_t>(r, b) ^ (1U << bit));
        }
      }
    }
    return d;
  }

  std::shared_ptr<KeyFrame> KeyFrameAt(Map& map, KeyFrameDatabase& db, int p) {
    static const auto camera = std::make_shared<Camera>(CameraConfig{});
    static const auto scale = std::make_shared<ScaleLevels>(features::MakeScaleLevels(1.2, 8));
    const cv::Mat d = View(p);
    std::vector<cv::KeyPoint> keys;
    for (int i = 0; i < d.rows; ++i) keys.emplace_back(20.f + 2.f * i, 240.f, 31.f, 0.f, 50.f, 0);
    const cv::Mat depth(480, 640, CV_16UC1, cv::Scalar(10000));
    auto kf = std::make_shared<KeyFrame>(map.NewKeyFrameId(), map.keyframes().size(), 0,
                                         MakeFeatures(keys, d, depth, camera, scale), SE3());
    kf->bow = db.Describe(d);
    map.AddKeyFrame(kf);
    db.Add(kf);
    return kf;
  }

  std::shared_ptr<const vocab::Vocabulary> vocabulary_;

 private:
  std::mt19937 rng_;
  std::vector<cv::Mat> place_;
};

TEST(KeyFrameDatabase, RelocalisationFindsTheKeyFrameOfTheSamePlace) {
  Places places(6);
  Map map;
  KeyFrameDatabase db(places.vocabulary_);
  std::vector<std::shared_ptr<KeyFrame>> kfs;
  for (int p = 0; p < 6; ++p) kfs.push_back(places.KeyFrameAt(map, db, p));
  for (int p = 0; p < 6; ++p) {
    const auto bow = db.Describe(places.View(p));
    const auto c = db.RelocalisationCandidates(bow->words);
    ASSERT_FALSE(c.empty());
    EXPECT_EQ(c.front().keyframe, kfs[static_cast<std::size_t>(p)]);
    EXPECT_GT(c.front().score, 0.3);
  }
  map.Clear();
}

TEST(KeyFrameDatabase, LoopCandidatesSkipConnectedKeyFramesAndErasedOnes) {
  Places places(4);
  Map map;
  KeyFrameDatabase db(places.vocabulary_);
  const auto old = places.KeyFrameAt(map, db, 0);
  const auto neighbour = places.KeyFrameAt(map, db, 0);
  const auto query = places.KeyFrameAt(map, db, 0);
  places.KeyFrameAt(map, db, 1);
  // query and neighbour share map points: connected, so not a loop.
  query->AddConnection(neighbour, 50);
  neighbour->AddConnection(query, 50);
  auto c = db.LoopCandidates(*query, 0.0);
  ASSERT_EQ(c.size(), 1U);
  EXPECT_EQ(c.front().keyframe, old);
  // A minimum score above every candidate's: none.
  EXPECT_TRUE(db.LoopCandidates(*query, 1.01).empty());
  db.Erase(*old);
  for (const auto& x : db.LoopCandidates(*query, 0.0)) EXPECT_NE(x.keyframe, old);
  map.Clear();
}

}  // namespace
}  // namespace sgslam
