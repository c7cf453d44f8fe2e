// Algorithm 1 and its ablation modes on synthetic scenes with known moving objects:
// precision and recall of the rejected keypoints against the ground-truth masks.
#include <gtest/gtest.h>

#include <map>

#include "dynamic/dynamic_test_scene.h"

namespace sgslam::dynamic {
namespace {

using test::FramePair;
using test::Score;

constexpr int kFirst = 5, kPairs = 16, kStride = 17;  // frames 5, 22, ..., 260 and their successors

struct Case {
  FramePair pair;
  std::vector<cv::KeyPoint> keys;
  std::vector<test::Truth> truth;
};

const Case& GetCase(const std::string& preset, int index) {
  static std::map<std::pair<std::string, int>, Case> cases;
  auto it = cases.find({preset, index});
  if (it != cases.end()) return it->second;
  Case c{test::MakePair(preset, index), {}, {}};
  c.keys = test::DetectKeypoints(c.pair.cur_gray);
  c.truth = test::Label(c.keys, c.pair.cur_dynamic);
  return cases.emplace(std::pair{preset, index}, std::move(c)).first->second;
}

// The configuration and the constants a run uses.
struct Settings {
  DynamicConfig config;
  Algorithm1Params params;
};

// The synthetic frames are noise-free (static d ~0.1 px): they are judged at
// eps_std 1 and the patch limit 12 (the real-data defaults are 3, dynamic_config.h,
// and kMaxPatchDifference 20, flow.h). The RGB-D check finds its motion by PnP on
// the pairs.
Settings Synthetic() {
  Settings s;
  s.config.eps_std = 1.0;
  s.params.flow.max_patch_difference = 12.0;
  return s;
}

Score Evaluate(const std::string& preset, const std::string& mode, Settings setup = Synthetic(),
               bool depth_check = false) {
  DynamicConfig& config = setup.config;
  config.mode = mode;
  config.refinements.depth_check = depth_check;
  Score score;
  for (int k = 0; k < kPairs; ++k) {
    const Case& c = GetCase(preset, kFirst + k * kStride);
    const FramePair& p = c.pair;
    const DepthCheckInput depth{p.prev_depth, p.cur_depth, 1.0, p.K, p.T_cur_prev, {}};
    const RejectionResult r = RejectDynamicFeatures(FlowFrame{p.prev_gray, {}}, FlowFrame{p.cur_gray, {}}, c.keys,
                                                    p.detections, test::PersonWeight, config, &depth, {},
                                                    setup.params);
    score.Add(r, c.truth);
  }
  return score;
}

TEST(Rejection, SgRejectsWalkersAndKeepsTheStaticScene) {
  const Score sg = Evaluate("walkers", "sg");
  sg.Print("walkers sg");
  EXPECT_GT(sg.dynamic, 300);
  EXPECT_GE(sg.Recall(), 0.90);
  EXPECT_LE(sg.StaticLoss(), 0.10);
}

TEST(Rejection, AblationModesOnWalkers) {
  const Score none = Evaluate("walkers", "none"), semantic = Evaluate("walkers", "semantic"),
              geometric = Evaluate("walkers", "geometric");
  none.Print("walkers none");
  semantic.Print("walkers semantic");
  geometric.Print("walkers geometric");
  EXPECT_EQ(none.dynamic_rejected + none.static_rejected, 0);
  EXPECT_GE(semantic.Recall(), 0.99);  // ground-truth boxes hold every walker pixel
  // The walkers cross the view sideways while the handheld camera also moves
  // sideways: much of their motion lies along the epipolar lines, so geometry alone
  // finds under half of them (measured 0.46 over 40 pairs) and sg needs w.
  EXPECT_GT(geometric.Recall(), 0.2);
  EXPECT_LT(geometric.Recall(), Evaluate("walkers", "sg").Recall());
  EXPECT_LE(geometric.StaticLoss(), 0.05);
  EXPECT_LE(semantic.StaticLoss(), 0.15);  // the static background inside the boxes
}

TEST(Rejection, EpipolarTestIsBlindToMotionAlongEpipolarLines) {
  const Score geometric = Evaluate("degenerate", "geometric"), sg = Evaluate("degenerate", "sg");
  geometric.Print("degenerate geometric");
  sg.Print("degenerate sg");
  EXPECT_GT(geometric.dynamic, 100);
  EXPECT_LT(geometric.Recall(), 0.6);  // the paper's named weakness
  Settings depth_only = Synthetic();
  depth_only.params.depth.reprojection_tolerance = 0;  // the walker moves sideways: its depth does not change
  const Score z_only = Evaluate("degenerate", "geometric", depth_only, true);
  z_only.Print("degenerate geometric + depth only");
  EXPECT_LT(z_only.Recall(), 0.6);
  const Score with_depth = Evaluate("degenerate", "geometric", Synthetic(), true);
  with_depth.Print("degenerate geometric + depth check");
  EXPECT_GE(with_depth.Recall(), 0.8);  // misses: walker and camera turning, < 3 px apart
  EXPECT_LE(with_depth.StaticLoss(), 0.02);
  const Score sg_depth = Evaluate("degenerate", "sg", Synthetic(), true);
  sg_depth.Print("degenerate sg + depth check");
  EXPECT_GE(sg_depth.Recall(), 0.9);
}

TEST(Rejection, WalkersWithDepthCheck) {
  for (const char* mode : {"geometric", "sg"}) {
    const Score s = Evaluate("walkers", mode, Synthetic(), true);
    s.Print((std::string("walkers ") + mode + " + depth check").c_str());
    EXPECT_GE(s.Recall(), 0.75);
    EXPECT_LE(s.StaticLoss(), 0.10);
  }
}

// The defaults (eps_std 3, RGB-D check with the PnP motion) on the synthetic scenes.
TEST(Rejection, DefaultsOnTheSyntheticPresets) {
  for (const char* preset : {"walkers", "degenerate"}) {
    const Score s = Evaluate(preset, "sg", Settings{}, true);
    s.Print((std::string(preset) + " sg, defaults").c_str());
    EXPECT_GE(s.Recall(), 0.80);  // measured 0.915 walkers, 0.846 degenerate (16 pairs, seed 1)
    EXPECT_LE(s.StaticLoss(), 0.10);
  }
  const Score st = Evaluate("static", "sg", Settings{}, true);
  st.Print("static sg, defaults");
  EXPECT_LE(st.StaticLoss(), 0.05);
}

TEST(Rejection, StaticSceneLosesFewKeypoints) {
  for (const char* mode : {"geometric", "sg"}) {
    const Score s = Evaluate("static", mode);
    s.Print((std::string("static ") + mode).c_str());
    EXPECT_EQ(s.dynamic, 0);
    EXPECT_LE(s.StaticLoss(), 0.05);
  }
}

}  // namespace
}  // namespace sgslam::dynamic
