#include "sgslam/features/quadtree.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace sgslam::features {

namespace {

struct Node {
  float x0, y0, x1, y1;
  std::vector<int> kps;  // indices into the input
};

// A node stops splitting when it holds one keypoint, or when it is down to a
// pixel (keypoints on the same pixel could otherwise be split forever).
bool Splittable(const Node& n) { return n.kps.size() > 1 && n.x1 - n.x0 > 1.0f && n.y1 - n.y0 > 1.0f; }

// The non-empty children of `n`, in a fixed order.
std::vector<Node> Split(const Node& n, const std::vector<cv::KeyPoint>& keypoints) {
  const float xm = 0.5f * (n.x0 + n.x1), ym = 0.5f * (n.y0 + n.y1);
  Node child[4] = {
      {n.x0, n.y0, xm, ym, {}}, {xm, n.y0, n.x1, ym, {}}, {n.x0, ym, xm, n.y1, {}}, {xm, ym, n.x1, n.y1, {}}};
  for (int i : n.kps) {
    const cv::Point2f& p = keypoints[static_cast<size_t>(i)].pt;
    child[(p.x >= xm ? 1 : 0) + (p.y >= ym ? 2 : 0)].kps.push_back(i);
  }
  std::vector<Node> out;
  for (Node& c : child) {
    if (!c.kps.empty()) out.push_back(std::move(c));
  }
  return out;
}

std::vector<Node> RootNodes(const std::vector<cv::KeyPoint>& keypoints, const cv::Rect2f& region) {
  const int n_roots = std::max(1, static_cast<int>(std::lround(region.width / region.height)));
  const float w = region.width / static_cast<float>(n_roots);
  std::vector<Node> roots;
  for (int i = 0; i < n_roots; ++i) {
    const float x0 = region.x + static_cast<float>(i) * w;
    roots.push_back({x0, region.y, x0 + w, region.y + region.height, {}});
  }
  for (size_t k = 0; k < keypoints.size(); ++k) {
    const int i = static_cast<int>((keypoints[k].pt.x - region.x) / w);
    roots[static_cast<size_t>(std::clamp(i, 0, n_roots - 1))].kps.push_back(static_cast<int>(k));
  }
  std::erase_if(roots, [](const Node& n) { return n.kps.empty(); });
  return roots;
}

// One refinement pass. While a full pass fits under `target`, every node splits:
// cells shrink uniformly over the image whatever its texture, which is what
// spreads the keypoints. Only the last pass, which would overshoot, splits the
// most crowded nodes first and stops at `target`.
std::vector<Node> SplitPass(std::vector<Node> nodes, const std::vector<cv::KeyPoint>& keypoints, size_t target) {
  std::vector<size_t> todo;
  for (size_t i = 0; i < nodes.size(); ++i) {
    if (Splittable(nodes[i])) todo.push_back(i);
  }
  if (nodes.size() + 3 * todo.size() > target) {
    std::stable_sort(todo.begin(), todo.end(),
                     [&](size_t a, size_t b) { return nodes[a].kps.size() > nodes[b].kps.size(); });
  }
  std::vector<std::vector<Node>> children(nodes.size());
  size_t count = nodes.size();
  for (size_t i : todo) {
    if (count >= target) break;
    children[i] = Split(nodes[i], keypoints);
    count += children[i].size() - 1;
  }
  std::vector<Node> next;
  next.reserve(count);
  for (size_t i = 0; i < nodes.size(); ++i) {
    if (children[i].empty()) {
      next.push_back(std::move(nodes[i]));
    } else {
      for (Node& c : children[i]) next.push_back(std::move(c));
    }
  }
  return next;
}

}  // namespace

std::vector<cv::KeyPoint> DistributeQuadtree(const std::vector<cv::KeyPoint>& keypoints, const cv::Rect2f& region,
                                             int target) {
  if (target <= 0 || keypoints.empty()) return {};
  const size_t n_target = static_cast<size_t>(target);
  std::vector<Node> nodes = RootNodes(keypoints, region);
  while (nodes.size() < n_target && std::any_of(nodes.begin(), nodes.end(), Splittable)) {
    nodes = SplitPass(std::move(nodes), keypoints, n_target);
  }

  std::vector<int> best;
  for (const Node& n : nodes) {
    int b = n.kps.front();
    for (int i : n.kps) {
      if (keypoints[static_cast<size_t>(i)].response > keypoints[static_cast<size_t>(b)].response) b = i;
    }
    best.push_back(b);
  }
  // Split children may push the count a few past the target (a node splits
  // into up to four), and there may be more roots than the target: drop the
  // weakest so exactly `target` remain.
  if (best.size() > n_target) {
    std::vector<size_t> order(best.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
      return keypoints[static_cast<size_t>(best[a])].response > keypoints[static_cast<size_t>(best[b])].response;
    });
    std::vector<bool> keep(best.size(), false);
    for (size_t k = 0; k < n_target; ++k) keep[order[k]] = true;
    std::vector<int> kept;
    for (size_t k = 0; k < best.size(); ++k) {
      if (keep[k]) kept.push_back(best[k]);
    }
    best.swap(kept);
  }
  std::vector<cv::KeyPoint> out;
  out.reserve(best.size());
  for (int i : best) out.push_back(keypoints[static_cast<size_t>(i)]);
  return out;
}

}  // namespace sgslam::features
