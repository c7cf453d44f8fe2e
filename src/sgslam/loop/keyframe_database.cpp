#include "sgslam/loop/keyframe_database.h"

#include <algorithm>
#include <unordered_map>

namespace sgslam {

namespace {
constexpr double kSharedWordsRatio = 0.8;  // of the most shared words (ORB-SLAM2)
constexpr double kPoolRatio = 0.75;        // of the best pool's score
constexpr std::size_t kPoolNeighbours = 10;
}  // namespace

void KeyFrameDatabase::Add(const std::shared_ptr<KeyFrame>& kf) {
  std::lock_guard lock(mutex_);
  for (const auto& [word, weight] : kf->bow->words) {
    if (word < index_.size()) index_[word].push_back(kf);
  }
}

void KeyFrameDatabase::Erase(const KeyFrame& kf) {
  if (!kf.bow) return;
  std::lock_guard lock(mutex_);
  for (const auto& [word, weight] : kf.bow->words) {
    if (word >= index_.size()) continue;
    auto& list = index_[word];
    list.erase(std::remove_if(list.begin(), list.end(), [&](const auto& k) { return k.get() == &kf; }), list.end());
  }
}

template <typename Skip>
std::vector<KeyFrameDatabase::Shared> KeyFrameDatabase::SharingWords(const vocab::BowVector& bow, Skip skip) const {
  std::unordered_map<const KeyFrame*, std::size_t> at;
  std::vector<Shared> out;
  std::lock_guard lock(mutex_);
  for (const auto& [word, weight] : bow) {
    if (word >= index_.size()) continue;
    for (const auto& kf : index_[word]) {
      auto [it, inserted] = at.emplace(kf.get(), out.size());
      if (inserted) {
        if (skip(*kf)) {
          it->second = SIZE_MAX;
          continue;
        }
        out.push_back({kf, 0});
      }
      if (it->second != SIZE_MAX) ++out[it->second].words;
    }
  }
  return out;
}

std::vector<PlaceCandidate> KeyFrameDatabase::Rank(const vocab::BowVector& bow, std::vector<Shared> shared,
                                                   double min_score) {
  int most = 0;
  for (const Shared& s : shared) most = std::max(most, s.words);
  const double min_words = kSharedWordsRatio * most;
  std::unordered_map<const KeyFrame*, double> score;
  for (const Shared& s : shared) {
    if (s.words <= min_words) continue;
    const double v = vocab::Score(bow, s.keyframe->bow->words);
    if (v >= min_score) score[s.keyframe.get()] = v;
  }
  std::vector<PlaceCandidate> pools;
  double best_pool = 0;
  for (const Shared& s : shared) {
    const auto own = score.find(s.keyframe.get());
    if (own == score.end()) continue;
    PlaceCandidate pool{s.keyframe, own->second, own->second};
    for (const auto& n : s.keyframe->Covisibles(kPoolNeighbours)) {
      const auto it = score.find(n.get());
      if (it == score.end()) continue;
      pool.pool_score += it->second;
      if (it->second > pool.score) pool.keyframe = n, pool.score = it->second;
    }
    best_pool = std::max(best_pool, pool.pool_score);
    pools.push_back(pool);
  }
  std::vector<PlaceCandidate> out;
  for (const PlaceCandidate& p : pools) {
    if (p.pool_score < kPoolRatio * best_pool) continue;
    const bool seen = std::any_of(out.begin(), out.end(), [&](const auto& o) { return o.keyframe == p.keyframe; });
    if (!seen) out.push_back(p);
  }
  std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.pool_score > b.pool_score; });
  return out;
}

std::vector<PlaceCandidate> KeyFrameDatabase::RelocalisationCandidates(const vocab::BowVector& bow) const {
  return Rank(bow, SharingWords(bow, [](const KeyFrame& k) { return k.bad(); }), 0);
}

std::vector<PlaceCandidate> KeyFrameDatabase::LoopCandidates(const KeyFrame& kf, double min_score) const {
  const auto skip = [&](const KeyFrame& k) { return k.bad() || &k == &kf || kf.Weight(k.id) > 0; };
  return Rank(kf.bow->words, SharingWords(kf.bow->words, skip), min_score);
}

}  // namespace sgslam
