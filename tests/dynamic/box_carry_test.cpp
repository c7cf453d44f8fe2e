// BoxCarrier (box_carry.h): a moving person's box survives the frames where the
// detector misses it, follows the flow, and gives way to a fresh detection; boxes
// that showed no motion, static classes and boxes that left the view are dropped.
#include <gtest/gtest.h>

#include "dynamic/dynamic_test_scene.h"
#include "sgslam/dynamic/box_carry.h"

namespace sgslam::dynamic {
namespace {

Detection Box(const std::string& name, float x, float y, float w, float h) {
  Detection d;
  d.class_name = name;
  d.class_id = name == "person" ? 0 : 56;
  d.score = 0.8f;
  d.box = cv::Rect2f(x, y, w, h);
  return d;
}

bool IsDynamic(const std::string& name) { return name == "person"; }

// Keypoints on a grid over the image; the part inside `moving` moved by `shift`
// since the previous frame, the rest stayed (a still camera).
struct Flow {
  std::vector<cv::Point2f> cur;
  FlowPairs pairs;
};

Flow GridFlow(const cv::Rect2f& moving, cv::Point2f shift) {
  Flow f;
  for (float y = 5; y < 480; y += 10) {
    for (float x = 5; x < 640; x += 10) {
      const cv::Point2f prev(x, y);
      const cv::Point2f cur = moving.contains(prev) ? prev + shift : prev;
      f.cur.push_back(cur);
      f.pairs.prev.push_back(prev);
      f.pairs.status.push_back(PairStatus::kOk);
    }
  }
  f.pairs.valid = static_cast<int>(f.cur.size());
  return f;
}

const cv::Size kImage(640, 480);

TEST(BoxCarry, AMissedWalkerKeepsItsBoxForTheConfiguredFramesFollowingTheFlow) {
  BoxCarrier carrier(3, 0.3, IsDynamic);
  const Detection person = Box("person", 200, 100, 100, 250);
  carrier.Remember({person}, {true});

  // Three frames without a detection: the box is carried and moves 6 px right a
  // frame with the person's keypoints (most of the box).
  cv::Rect2f expected = person.box;
  for (int frame = 1; frame <= 3; ++frame) {
    const Flow flow = GridFlow(expected, cv::Point2f(6.f, 0.f));
    const std::vector<Detection> carried = carrier.Carry({}, flow.cur, flow.pairs, kImage);
    ASSERT_EQ(carried.size(), 1u) << "frame " << frame;
    expected += cv::Point2f(6.f, 0.f);
    EXPECT_NEAR(carried[0].box.x, expected.x, 1e-3) << "frame " << frame;
    EXPECT_NEAR(carried[0].box.y, expected.y, 1e-3);
    EXPECT_EQ(carried[0].carried, frame);
    EXPECT_EQ(carried[0].class_name, "person");
    carrier.Remember(carried, {true});  // still moving
  }
  // The fourth frame: three frames is the limit.
  const Flow flow = GridFlow(expected, cv::Point2f(6.f, 0.f));
  EXPECT_TRUE(carrier.Carry({}, flow.cur, flow.pairs, kImage).empty());
}

TEST(BoxCarry, AFreshDetectionOfTheSameObjectReplacesTheCarriedBox) {
  BoxCarrier carrier(5, 0.3, IsDynamic);
  carrier.Remember({Box("person", 200, 100, 100, 250)}, {true});
  const Detection again = Box("person", 205, 102, 100, 250);  // IoU ~0.9
  const Flow still = GridFlow(cv::Rect2f(), cv::Point2f());
  EXPECT_TRUE(carrier.Carry({again}, still.cur, still.pairs, kImage).empty());
  // A detection elsewhere (another person) does not replace it.
  carrier.Remember({Box("person", 200, 100, 100, 250)}, {true});
  const std::vector<Detection> carried =
      carrier.Carry({Box("person", 450, 100, 100, 250)}, still.cur, still.pairs, kImage);
  ASSERT_EQ(carried.size(), 1u);
  EXPECT_NEAR(carried[0].box.x, 200.f, 1e-3);
}

TEST(BoxCarry, BoxesWithoutMotionStaticClassesAndBoxesThatLeftTheViewAreNotCarried) {
  const Flow still = GridFlow(cv::Rect2f(), cv::Point2f());
  BoxCarrier carrier(5, 0.3, IsDynamic);
  // A person who showed no motion of their own (sitting, or a false positive).
  carrier.Remember({Box("person", 200, 100, 100, 250)}, {false});
  EXPECT_TRUE(carrier.Carry({}, still.cur, still.pairs, kImage).empty());
  // A chair is not a moving-object class.
  carrier.Remember({Box("chair", 200, 300, 100, 100)}, {true});
  EXPECT_TRUE(carrier.Carry({}, still.cur, still.pairs, kImage).empty());
  // A walker leaving at the right edge: after a 60 px shift less than a third of the box is in view.
  const Detection leaving = Box("person", 560, 100, 70, 250);
  carrier.Remember({leaving}, {true});
  const Flow out = GridFlow(leaving.box, cv::Point2f(60.f, 0.f));
  EXPECT_TRUE(carrier.Carry({}, out.cur, out.pairs, kImage).empty());
  // Carrying off: nothing is remembered.
  BoxCarrier off(0, 0.3, IsDynamic);
  off.Remember({Box("person", 200, 100, 100, 250)}, {true});
  EXPECT_TRUE(off.Carry({}, still.cur, still.pairs, kImage).empty());
}

TEST(BoxCarry, WithoutFlowTheBoxStaysWhereItWas) {
  BoxCarrier carrier(2, 0.3, IsDynamic);
  carrier.Remember({Box("person", 200, 100, 100, 250)}, {true});
  const std::vector<Detection> carried = carrier.Carry({}, {}, FlowPairs{}, kImage);
  ASSERT_EQ(carried.size(), 1u);
  EXPECT_EQ(carried[0].box, cv::Rect2f(200, 100, 100, 250));
}

// A carried box weighs the keypoints in it as its class does, but leaves the F and
// PnP fits alone: where it has drifted off its object it would otherwise hand the
// fits to whatever moves. On a walkers pair, a carried person box over static
// ground leaves every verdict outside it as without the box, while a fresh one changes F.
TEST(BoxCarry, ACarriedBoxWeighsKeypointsButLeavesTheFitsAlone) {
  const test::FramePair p = test::MakePair("walkers", 40);
  const std::vector<cv::KeyPoint> keys = test::DetectKeypoints(p.cur_gray);
  DynamicConfig config;
  config.mode = "sg";
  config.eps_std = 1.0;
  Algorithm1Params params;  // the synthetic frames' settings (rejection_test.cpp)
  params.flow.max_patch_difference = 12.0;
  const auto judge = [&](const std::vector<Detection>& boxes) {
    return RejectDynamicFeatures(FlowFrame{p.prev_gray, {}}, FlowFrame{p.cur_gray, {}}, keys, boxes,
                                 test::PersonWeight, config, nullptr, {}, params);
  };
  Detection ghost = Box("person", 0, 0, 320, 480);  // the left half of the image
  ghost.carried = 2;
  const RejectionResult base = judge(p.detections);
  std::vector<Detection> with_ghost = p.detections;
  with_ghost.push_back(ghost);
  const RejectionResult carried = judge(with_ghost);
  with_ghost.back().carried = 0;
  const RejectionResult fresh = judge(with_ghost);
  ASSERT_TRUE(base.fundamental && carried.fundamental && fresh.fundamental);
  EXPECT_TRUE(base.fundamental->F_cur_prev.isApprox(carried.fundamental->F_cur_prev));
  EXPECT_FALSE(base.fundamental->F_cur_prev.isApprox(fresh.fundamental->F_cur_prev));
  int inside = 0;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    if (ghost.box.contains(keys[i].pt)) {
      ++inside;
      EXPECT_EQ(carried.keypoints[i].weight, 5.0);
    } else {
      EXPECT_EQ(carried.keypoints[i].kept, base.keypoints[i].kept) << "keypoint " << i;
    }
  }
  EXPECT_GT(inside, 100);
}

TEST(BoxCarry, IouOfBoxes) {
  EXPECT_DOUBLE_EQ(BoxIou(cv::Rect2f(0, 0, 10, 10), cv::Rect2f(0, 0, 10, 10)), 1.0);
  EXPECT_NEAR(BoxIou(cv::Rect2f(0, 0, 10, 10), cv::Rect2f(5, 0, 10, 10)), 50.0 / 150.0, 1e-6);
  EXPECT_DOUBLE_EQ(BoxIou(cv::Rect2f(0, 0, 10, 10), cv::Rect2f(20, 0, 10, 10)), 0.0);
  EXPECT_DOUBLE_EQ(BoxIou(cv::Rect2f(), cv::Rect2f()), 0.0);
}

}  // namespace
}  // namespace sgslam::dynamic
