#include "sgslam/dynamic/box_carry.h"

#include <algorithm>

namespace sgslam::dynamic {

namespace {

// Median of v (v is reordered); v must not be empty.
float MedianOf(std::vector<float>& v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// Fewer flow pairs than this inside a box: it is not shifted (too few to tell).
constexpr std::size_t kMinShiftPairs = 5;

}  // namespace

double BoxIou(const cv::Rect2f& a, const cv::Rect2f& b) {
  const float inter = (a & b).area();
  const float uni = a.area() + b.area() - inter;
  return uni > 0 ? inter / uni : 0.0;
}

std::optional<cv::Rect2f> FollowBox(const cv::Rect2f& box, const std::vector<cv::Point2f>& cur, const FlowPairs& flow,
                                    cv::Size image) {
  // Where the box's content went: keypoints of this frame whose previous position
  // lies in the box, displacement previous -> current.
  std::vector<float> dx, dy;
  if (flow.prev.size() == cur.size() && flow.status.size() == cur.size()) {
    for (std::size_t i = 0; i < cur.size(); ++i) {
      if (flow.status[i] != PairStatus::kOk || !box.contains(flow.prev[i])) continue;
      dx.push_back(cur[i].x - flow.prev[i].x);
      dy.push_back(cur[i].y - flow.prev[i].y);
    }
  }
  cv::Rect2f moved = box;
  if (dx.size() >= kMinShiftPairs) moved += cv::Point2f(MedianOf(dx), MedianOf(dy));
  const cv::Rect2f frame(0.f, 0.f, static_cast<float>(image.width), static_cast<float>(image.height));
  const cv::Rect2f inside = moved & frame;
  // A box that left the image (less than a third of it still in view) is gone.
  if (inside.area() <= 0.f || inside.area() < moved.area() / 3.f) return std::nullopt;
  return inside;
}

std::vector<Detection> BoxCarrier::Carry(const std::vector<Detection>& fresh, const std::vector<cv::Point2f>& cur,
                                         const FlowPairs& flow, cv::Size image) {
  std::vector<Detection> out;
  if (frames_ <= 0) return out;
  for (Detection c : boxes_) {
    // Seen again in this frame: the fresh detection takes over.
    const bool found = std::any_of(fresh.begin(), fresh.end(), [&](const Detection& d) {
      return d.class_name == c.class_name && BoxIou(d.box, c.box) >= min_iou_;
    });
    if (found || c.carried >= frames_) continue;
    const std::optional<cv::Rect2f> moved = FollowBox(c.box, cur, flow, image);
    if (!moved) continue;
    c.box = *moved;
    ++c.carried;
    out.push_back(c);
  }
  boxes_.clear();
  return out;
}

void BoxCarrier::Remember(const std::vector<Detection>& boxes, const std::vector<bool>& moving) {
  boxes_.clear();
  if (frames_ <= 0) return;
  for (std::size_t i = 0; i < boxes.size() && i < moving.size(); ++i) {
    if (moving[i] && is_dynamic_ && is_dynamic_(boxes[i].class_name)) boxes_.push_back(boxes[i]);
  }
}

}  // namespace sgslam::dynamic
