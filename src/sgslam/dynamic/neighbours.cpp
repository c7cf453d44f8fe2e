#include "sgslam/dynamic/neighbours.h"

namespace sgslam::dynamic {

std::vector<std::size_t> UnjudgedAmongMovers(const std::vector<cv::KeyPoint>& keys,
                                             const std::vector<KeypointVerdict>& verdicts, double radius,
                                             double share, int min_judged) {
  std::vector<std::size_t> out;
  if (radius <= 0 || keys.size() != verdicts.size()) return out;
  const double r2 = radius * radius;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    if (!verdicts[i].kept || verdicts[i].why != Why::kUnjudged) continue;
    int judged = 0, rejected = 0;
    for (std::size_t j = 0; j < keys.size(); ++j) {
      const Why why = verdicts[j].why;
      if (why != Why::kStatic && why != Why::kGeometry && why != Why::kDepth) continue;
      const cv::Point2f d = keys[j].pt - keys[i].pt;
      if (d.x * d.x + d.y * d.y > r2) continue;
      ++judged;
      rejected += !verdicts[j].kept;
    }
    if (judged >= min_judged && rejected > share * judged) out.push_back(i);
  }
  return out;
}

}  // namespace sgslam::dynamic
