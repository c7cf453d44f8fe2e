// Association of two timestamp lists exactly as TUM's associate.py does it: every
// pair closer than max_difference is a candidate; candidates are taken greedily in
// order of increasing |difference| (ties by first, then second timestamp), each
// timestamp used once; the result is sorted by the first timestamp.
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

#include "sgslam/common/time.h"

namespace sgslam {

// first and second must be sorted ascending. Returns index pairs (i, j) with
// |first[i] - (second[j] + offset)| < max_difference.
std::vector<std::pair<std::size_t, std::size_t>> AssociateByTime(const std::vector<Timestamp>& first,
                                                                 const std::vector<Timestamp>& second,
                                                                 Timestamp max_difference, Timestamp offset = 0);

}  // namespace sgslam
