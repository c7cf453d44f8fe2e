// The projection searches of tracking (features/matcher.h) and rejected keypoints:
// with a distance of 0 (tracking.refinements.rejected_matches off) a rejected keypoint is never matched;
// with 50, only to a trusted map point that no kept keypoint matched, and only
// within that descriptor distance.
#include "sgslam/matching/matcher.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <random>
#include <vector>

#include "sgslam/camera/camera.h"
#include "sgslam/features/pyramid.h"
#include "sgslam/map/keyframe.h"
#include "sgslam/map/map_point.h"

namespace sgslam {
namespace {

// A keypoint of the frame, and the map point of the same index: it projects onto
// the keypoint and its descriptor is the keypoint's with `flipped` bits changed.
struct Key {
  float u, v;
  bool rejected;
  int flipped;  // bits the map point's descriptor differs by from this keypoint's
  bool trusted;
};

class RejectedMatching : public ::testing::Test {
 protected:
  // 0: kept, trusted point: matched always.
  // 1: rejected, trusted point: matched only with the option.
  // 2: rejected, untrusted point: never.
  // 3: rejected, trusted point 70 bits away (beyond 50, within kThHigh): never.
  // 4: kept, trusted point 30 bits away; 5, 3 px beside it, rejected, 0 bits away
  //    from that same point: the kept keypoint keeps it. Point 5 is absent.
  const std::vector<Key> keys_ = {{100, 100, false, 0, true},  {200, 150, true, 0, true},
                                  {300, 200, true, 0, false},  {400, 250, true, 70, true},
                                  {500, 300, false, 30, true}, {503, 300, true, 0, true}};

  void SetUp() override {
    camera_ = std::make_shared<Camera>(CameraConfig{});
    scale_ = std::make_shared<ScaleLevels>(features::MakeScaleLevels(1.2, 8));
    std::mt19937 rng(7);
    std::uniform_int_distribution<int> byte(0, 255);
    std::vector<cv::KeyPoint> keys;
    std::vector<std::uint8_t> dynamic;
    cv::Mat frame_desc(static_cast<int>(keys_.size()), 32, CV_8U), map_desc;
    for (std::size_t i = 0; i < keys_.size(); ++i) {
      keys.emplace_back(keys_[i].u, keys_[i].v, 31.f, 0.f, 1.f, 0);
      dynamic.push_back(keys_[i].rejected ? 1 : 0);
      for (int b = 0; b < 32; ++b) frame_desc.at<std::uint8_t>(static_cast<int>(i), b) = static_cast<std::uint8_t>(byte(rng));
    }
    map_desc = frame_desc.clone();
    for (std::size_t i = 0; i < keys_.size(); ++i) {
      for (int bit = 0; bit < keys_[i].flipped; ++bit) map_desc.at<std::uint8_t>(static_cast<int>(i), bit / 8) ^= 1u << (bit % 8);
    }
    map_desc.row(4).copyTo(frame_desc.row(5));  // keypoint 5 carries point 4's descriptor exactly
    const cv::Mat no_depth(480, 640, CV_16UC1, cv::Scalar(0));
    features_ = MakeFeatures(keys, frame_desc, no_depth, camera_, scale_, dynamic);
    const auto map_features = MakeFeatures(keys, map_desc, no_depth, camera_, scale_);
    keyframe_ = std::make_shared<KeyFrame>(0, 0, 0, map_features, SE3());
    for (std::size_t i = 0; i + 1 < keys_.size(); ++i) {  // no point 5
      const cv::Point2f un = features_->keys_un[i].pt;
      auto p = std::make_shared<MapPoint>(i, camera_->Unproject(un.x, un.y, 2.0), keyframe_);
      p->AddObservation(keyframe_, i);
      p->UpdateDescriptor();
      p->track.trusted = keys_[i].trusted;
      points_.push_back(p);
    }
  }

  Frame MakeFrame() const { return Frame(1, 1, features_); }

  // Local-map search: the points carry their projections as Frame::IsInFrustum would.
  std::vector<std::shared_ptr<MapPoint>> Predicted() const {
    for (std::size_t i = 0; i < points_.size(); ++i) {
      auto& t = points_[i]->track;
      t.in_view = true;
      t.u = features_->keys_un[i].pt.x;
      t.v = features_->keys_un[i].pt.y;
      t.u_right = -1;
      t.view_cos = 1;
      t.predicted_level = 0;
      t.last_frame_seen = 0;
    }
    return points_;
  }

  // Which point each keypoint got (-1: none).
  static std::vector<int> Matched(const Frame& f) {
    std::vector<int> out;
    for (const auto& p : f.map_points) out.push_back(p ? static_cast<int>(p->id) : -1);
    return out;
  }

  std::shared_ptr<Camera> camera_;
  std::shared_ptr<ScaleLevels> scale_;
  std::shared_ptr<const Features> features_;
  std::shared_ptr<KeyFrame> keyframe_;
  std::vector<std::shared_ptr<MapPoint>> points_;
};

TEST_F(RejectedMatching, LocalMapSearch) {
  Frame off = MakeFrame();
  EXPECT_EQ(matcher::SearchLocalPoints(off, Predicted(), 3.0, 0), 2);
  EXPECT_EQ(Matched(off), (std::vector<int>{0, -1, -1, -1, 4, -1}));

  Frame on = MakeFrame();
  EXPECT_EQ(matcher::SearchLocalPoints(on, Predicted(), 3.0, 50), 3);
  EXPECT_EQ(Matched(on), (std::vector<int>{0, 1, -1, -1, 4, -1}));
}

TEST_F(RejectedMatching, MotionModelSearch) {
  // The last frame saw every point at the same place (camera still).
  Frame last(0, 0, keyframe_->features);
  for (std::size_t i = 0; i < points_.size(); ++i) last.map_points[i] = points_[i];
  for (const bool option : {false, true}) {
    Frame cur = MakeFrame();
    const int n = matcher::SearchByProjection(cur, last, 7.5, option ? 50 : 0);
    if (option) {
      EXPECT_EQ(n, 3);
      EXPECT_EQ(Matched(cur), (std::vector<int>{0, 1, -1, -1, 4, -1}));
    } else {
      EXPECT_EQ(n, 2);
      EXPECT_EQ(Matched(cur), (std::vector<int>{0, -1, -1, -1, 4, -1}));
    }
  }
}

}  // namespace
}  // namespace sgslam
