#include "sgslam/io/association.h"

#include <algorithm>
#include <cstdlib>
#include <tuple>

namespace sgslam {

std::vector<std::pair<std::size_t, std::size_t>> AssociateByTime(const std::vector<Timestamp>& first,
                                                                 const std::vector<Timestamp>& second,
                                                                 Timestamp max_difference, Timestamp offset) {
  // Candidates within the window, found with a sliding lower bound instead of the
  // quadratic scan of associate.py; the greedy order below is the same.
  std::vector<std::tuple<Timestamp, std::size_t, std::size_t>> candidates;
  std::size_t lo = 0;
  for (std::size_t i = 0; i < first.size(); ++i) {
    while (lo < second.size() && second[lo] + offset <= first[i] - max_difference) ++lo;
    for (std::size_t j = lo; j < second.size() && second[j] + offset < first[i] + max_difference; ++j) {
      candidates.emplace_back(std::llabs(first[i] - (second[j] + offset)), i, j);
    }
  }
  std::sort(candidates.begin(), candidates.end());
  std::vector<char> used_first(first.size(), 0), used_second(second.size(), 0);
  std::vector<std::pair<std::size_t, std::size_t>> matches;
  for (const auto& [diff, i, j] : candidates) {
    if (used_first[i] || used_second[j]) continue;
    used_first[i] = used_second[j] = 1;
    matches.emplace_back(i, j);
  }
  std::sort(matches.begin(), matches.end());
  return matches;
}

}  // namespace sgslam
