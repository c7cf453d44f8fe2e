// The place-recognition database (ORB-SLAM2's KeyFrameDatabase): an inverted
// index from each vocabulary word to the keyframes whose bag of words holds it,
// queried for relocalisation (which keyframes look like this frame?) and for loop
// detection (which keyframe, not already a neighbour, looks like this one?).
//
// Candidates are scored as ORB-SLAM2 does: keyframes sharing at least 80 % of the
// most shared words are scored by bag of words; each candidate's score is pooled
// with those of its 10 best covisible keyframes that are candidates too, and the
// best keyframe of every pool within 75 % of the best pool is returned.
//
// Threading: Add/Erase/queries from any thread. The database's own mutex is a
// leaf lock: it is never held while the map's lock is taken. Queries read the
// covisibility graph, so callers hold Map::mutex() shared (map lock, then the
// database's: the only order).
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "sgslam/map/keyframe.h"
#include "sgslam/vocab/vocabulary.h"

namespace sgslam {

struct PlaceCandidate {
  std::shared_ptr<KeyFrame> keyframe;
  double score = 0;        // bag-of-words score with the query
  double pool_score = 0;   // with its covisible candidates
};

class KeyFrameDatabase {
 public:
  explicit KeyFrameDatabase(std::shared_ptr<const vocab::Vocabulary> vocabulary)
      : vocabulary_(std::move(vocabulary)), index_(vocabulary_->size()) {}

  const vocab::Vocabulary& vocabulary() const { return *vocabulary_; }
  // The bag of words of an image's descriptors, with its direct index at the
  // level ORB-SLAM2 matches at (kDirectIndexLevelsUp above the leaves).
  std::shared_ptr<const vocab::BowData> Describe(const cv::Mat& descriptors) const {
    return std::make_shared<const vocab::BowData>(vocabulary_->Transform(descriptors, kDirectIndexLevelsUp));
  }
  static constexpr int kDirectIndexLevelsUp = 3;

  // kf->bow must be set. Adding a keyframe twice is an error the map check would
  // see as a duplicate candidate; do not.
  void Add(const std::shared_ptr<KeyFrame>& kf);
  void Erase(const KeyFrame& kf);

  // Keyframes that may show the place a lost frame sees, best pool first.
  std::vector<PlaceCandidate> RelocalisationCandidates(const vocab::BowVector& bow) const;
  // Keyframes that may close a loop with kf: not connected to it in the
  // covisibility graph, scoring at least min_score (ORB-SLAM2: the lowest score
  // between kf and its covisible keyframes), best pool first.
  std::vector<PlaceCandidate> LoopCandidates(const KeyFrame& kf, double min_score) const;

 private:
  struct Shared {
    std::shared_ptr<KeyFrame> keyframe;
    int words = 0;
  };
  // Keyframes sharing words with bow, with the count, but for those skip() rejects.
  template <typename Skip>
  std::vector<Shared> SharingWords(const vocab::BowVector& bow, Skip skip) const;
  static std::vector<PlaceCandidate> Rank(const vocab::BowVector& bow, std::vector<Shared> shared, double min_score);

  const std::shared_ptr<const vocab::Vocabulary> vocabulary_;
  mutable std::mutex mutex_;
  std::vector<std::vector<std::shared_ptr<KeyFrame>>> index_;  // word -> keyframes
};

}  // namespace sgslam
