// Scoring mover tracks against true movers: coverage, id switches (CLEAR MOT's
// rule), false tracks, centroid error; and the truth of dyn_dev computed from its
// masks, depth and object positions.
#include "sgslam/eval/track_score.h"

#include <gtest/gtest.h>

#include "support/test_support.h"

namespace sgslam::eval {
namespace {

constexpr Timestamp kFrame = 33'333'333;

Trajectory Still(int frames) {
  Trajectory t;
  for (int k = 0; k < frames; ++k) t.push_back({k * kFrame, SE3(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.01 * k, 0, 0))});
  return t;
}

movers::TrackLine Line(int k, int id, const Eigen::Vector3d& p,
                       movers::TrackState state = movers::TrackState::kConfirmed) {
  movers::TrackLine l;
  l.t = k * kFrame;
  l.id = id;
  l.class_name = "person";
  l.position = p;
  l.state = state;
  return l;
}

TEST(TrackScore, CountsCoverageSwitchesAndFalseTracks) {
  const int frames = 100;
  MoverTruth truth;
  truth.image_pixels = 1000;
  std::vector<movers::TrackLine> tracks;
  for (int k = 0; k < frames; ++k) {
    const Eigen::Vector3d p(1.0 + 0.01 * k, 2, 1);
    truth.frames[k * kFrame].push_back({7, "person", k < 50 ? 500 : 50, p});  // large, then under 10 %
    if (k < 10) continue;                                                   // found from frame 10
    const int id = k < 60 ? 1 : 2;                                          // one switch at 60
    tracks.push_back(Line(k, id, p + Eigen::Vector3d(0.05, 0, 0)));
    if (k >= 20 && k < 25) tracks.push_back(Line(k, 9, p + Eigen::Vector3d(0, 0.2, 0)));  // a second track near it
    tracks.push_back(Line(k, 5, Eigen::Vector3d(5, 5, 5)));  // far from any mover: false
    tracks.push_back(Line(k, 6, Eigen::Vector3d(5, 6, 5), movers::TrackState::kTentative));  // not counted
  }
  const TrackScore s = ScoreTracks(truth, tracks, Still(frames), Still(frames));
  EXPECT_EQ(s.frames, frames);
  ASSERT_EQ(s.movers.size(), 1u);
  EXPECT_EQ(s.movers[0].frames_visible, 50);
  EXPECT_EQ(s.movers[0].frames_covered, 40);
  EXPECT_DOUBLE_EQ(s.coverage, 0.8);
  EXPECT_EQ(s.movers[0].id_switches, 1);  // track 9, nearer for 5 frames, does not take it over
  EXPECT_EQ(s.false_tracks, 2);           // 5, and 9 that never covered the mover
  EXPECT_DOUBLE_EQ(s.false_per_100_frames, 2.0);
  EXPECT_NEAR(s.median_centroid_error, 0.05, 1e-6);
}

TEST(TrackScore, DynDevTruthMatchesTheGeneratorsPixelCounts) {
  SGSLAM_REQUIRE_SHARED(dir, "data/dyn_dev");
  CameraConfig camera;  // TUM fr1, the sequence's
  const std::optional<MoverTruth> truth = LoadMoverTruth(dir, camera);
  ASSERT_TRUE(truth);
  ASSERT_EQ(truth->frames.size(), 300u);
  // frame_stats.txt of the first frame: object 0 covers 43678 px, object 1 546, object 2 none.
  const std::vector<TrueMover>& first = truth->frames.begin()->second;
  ASSERT_EQ(first.size(), 2u);
  EXPECT_NEAR(first[0].pixels, 43678, 0.02 * 43678);
  EXPECT_NEAR(first[1].pixels, 546, 100);
  // A person's visible centre is on its quad, between the floor and its 1.7 m.
  EXPECT_GT(first[0].centroid.z(), 0.0);
  EXPECT_LT(first[0].centroid.z(), 1.7);
}

}  // namespace
}  // namespace sgslam::eval
