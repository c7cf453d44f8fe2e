// The object database's association, class vote, belief and removal
// (semantic/objects.h) on synthetic views with exact poses.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "sgslam/map/features.h"
#include "sgslam/map/keyframe.h"
#include "sgslam/semantic/object_sizes.h"
#include "sgslam/semantic/objects.h"

namespace sgslam {
namespace {

constexpr double kF = 500, kCx = 320, kCy = 240;

Eigen::Vector2d Project(const Eigen::Vector3d& p) { return {kF * p.x() / p.z() + kCx, kF * p.y() / p.z() + kCy}; }

// A camera at the origin turned by yaw degrees about its y axis (x right, y down, z forward).
SE3 Turned(double yaw_deg, const Eigen::Vector3d& at = Eigen::Vector3d::Zero()) {
  return SE3(Eigen::Quaterniond(Eigen::AngleAxisd(yaw_deg * M_PI / 180, Eigen::Vector3d::UnitY())), at);
}

// Samples on the faces of an axis-aligned box (world frame).
std::vector<Eigen::Vector3d> BoxSurface(const Eigen::Vector3d& centre, const Eigen::Vector3d& size) {
  std::vector<Eigen::Vector3d> out;
  for (int i = 0; i <= 12; ++i) {
    for (int j = 0; j <= 12; ++j) {
      const double a = i / 12.0 - 0.5, b = j / 12.0 - 0.5;
      for (double s : {-0.5, 0.5}) {
        out.push_back(centre + Eigen::Vector3d(s, a, b).cwiseProduct(size));
        out.push_back(centre + Eigen::Vector3d(a, s, b).cwiseProduct(size));
        out.push_back(centre + Eigen::Vector3d(a, b, s).cwiseProduct(size));
      }
    }
  }
  return out;
}

// The view from T_w_c of the samples (those in front of it), with their box in the image.
ObjectObservation View(const std::string& class_name, int class_id, const std::vector<Eigen::Vector3d>& world,
                       const SE3& T_w_c, float score = 0.8f, std::shared_ptr<KeyFrame> keyframe = nullptr) {
  ObjectObservation o;
  o.class_id = class_id;
  o.class_name = class_name;
  o.score = score;
  o.keyframe = std::move(keyframe);
  const SE3 T_c_w = T_w_c.Inverse();
  Eigen::Vector2d lo(1e9, 1e9), hi(-1e9, -1e9);
  for (const auto& x : world) {
    const Eigen::Vector3d p = T_c_w * x;
    if (p.z() <= 0.1) continue;
    o.points_c.push_back(p.cast<float>());
    lo = lo.cwiseMin(Project(p));
    hi = hi.cwiseMax(Project(p));
  }
  o.box = cv::Rect2f(static_cast<float>(lo.x()), static_cast<float>(lo.y()), static_cast<float>(hi.x() - lo.x()),
                     static_cast<float>(hi.y() - lo.y()));
  return o;
}

ObjectDatabase MakeDatabase() { return ObjectDatabase(SemanticConfig(), Project, cv::Size(640, 480)); }

SE3 Identity(const KeyFrame&) { return SE3(); }

const ObjectEstimate* Find(const std::vector<ObjectEstimate>& all, int id) {
  for (const auto& e : all) {
    if (e.id == id) return &e;
  }
  return nullptr;
}

// A depth image (16-bit, factor 5000) of a plane at depth z, or of nothing (0).
cv::Mat DepthPlane(double z) { return cv::Mat(480, 640, CV_16UC1, cv::Scalar(z > 0 ? z * 5000 : 0)); }

// One object that the detector names two ways (a monitor it sometimes calls a
// laptop) is one object whose class is the histogram's winner; a keyboard just in
// front of it and a table under both stay objects of their own.
TEST(ObjectDatabase, AssociatesIn3DAndVotesTheClass) {
  ObjectDatabase db = MakeDatabase();
  const auto monitor = BoxSurface({0, -0.3, 2.0}, {0.55, 0.35, 0.05});
  const auto keyboard = BoxSurface({0, 0.0, 1.75}, {0.45, 0.03, 0.15});
  const auto table = BoxSurface({0, 0.1, 1.9}, {1.6, 0.05, 0.8});
  const int id = db.Add(View("tvmonitor", 62, monitor, Turned(0)), Turned(0));
  EXPECT_EQ(db.Add(View("laptop", 63, monitor, Turned(5), 0.9f), Turned(5)), id);  // another label, same place
  EXPECT_EQ(db.Add(View("tvmonitor", 62, monitor, Turned(10)), Turned(10)), id);
  EXPECT_EQ(db.Add(View("tvmonitor", 62, monitor, Turned(-5)), Turned(-5)), id);
  const int kb = db.Add(View("keyboard", 66, keyboard, Turned(0)), Turned(0));
  const int tb = db.Add(View("diningtable", 60, table, Turned(0)), Turned(0));
  EXPECT_NE(kb, id);
  EXPECT_NE(tb, id);
  EXPECT_NE(tb, kb);
  // The keyboard seen again joins the keyboard, not the table its samples lie on.
  EXPECT_EQ(db.Add(View("keyboard", 66, keyboard, Turned(8)), Turned(8)), kb);
  const auto all = db.Estimate(Identity);
  ASSERT_EQ(all.size(), 3u);
  const ObjectEstimate* m = Find(all, id);
  ASSERT_NE(m, nullptr);
  EXPECT_EQ(m->class_name, "tvmonitor");
  EXPECT_NEAR(m->class_share, 2.4 / 3.3, 1e-6);
  EXPECT_EQ(m->observations, 4);
  EXPECT_NEAR(m->centroid.y(), -0.3, 0.03);
  EXPECT_NEAR(m->dimensions.x(), 0.55, 0.03);
  EXPECT_TRUE(m->confirmed);
  EXPECT_TRUE(m->plausible);
  EXPECT_TRUE(m->exported);
}

// Belief needs evidence: views from three keyframes, a viewpoint change, and a
// detection in enough of the keyframes the object was in view of.
TEST(ObjectDatabase, ConfirmsFromViewsSpreadOverAViewpointChange) {
  const auto chair = BoxSurface({0, 0, 2.5}, {0.5, 0.9, 0.5});
  {
    ObjectDatabase db = MakeDatabase();  // three views from one place: a detector's repeated mistake
    for (int k = 0; k < 3; ++k) db.Add(View("chair", 56, chair, Turned(0)), Turned(0));
    const auto all = db.Estimate(Identity);
    ASSERT_EQ(all.size(), 1u);
    EXPECT_EQ(all[0].observations, 3);
    EXPECT_LT(all[0].spread_deg, 1.0);
    EXPECT_FALSE(all[0].confirmed);
    EXPECT_FALSE(all[0].exported);
  }
  ObjectDatabase db = MakeDatabase();
  db.Add(View("chair", 56, chair, Turned(0)), Turned(0));
  db.Add(View("chair", 56, chair, Turned(7)), Turned(7));
  auto all = db.Estimate(Identity);
  EXPECT_FALSE(all[0].confirmed);  // two views
  const int id = db.Add(View("chair", 56, chair, Turned(14)), Turned(14));
  all = db.Estimate(Identity);
  EXPECT_GT(all[0].spread_deg, kObjectMinSpreadDeg);
  EXPECT_TRUE(all[0].confirmed);
  // In view, unoccluded (the depth is the chair's front), and not detected, many times over.
  const cv::Mat depth = DepthPlane(2.25);
  for (int k = 0; k < 12; ++k) EXPECT_EQ(db.CountViews({}, Turned(7), depth, 5000), 0);
  all = db.Estimate(Identity);
  EXPECT_EQ(all[0].views_expected, 12);
  EXPECT_EQ(all[0].views_seen, 0);
  EXPECT_FALSE(all[0].confirmed);  // seen in 3 of the 15 keyframes it was in view of
  // Detected again, and counted as seen (5 of the 17 keyframes it was in view of).
  for (int k = 0; k < 5; ++k) {
    EXPECT_EQ(db.Add(View("chair", 56, chair, Turned(3 * k)), Turned(3 * k)), id);
    db.CountViews({id}, Turned(3 * k), depth, 5000);
  }
  all = db.Estimate(Identity);
  EXPECT_EQ(all[0].views_seen, 5);
  EXPECT_EQ(all[0].views_expected, 17);
  EXPECT_TRUE(all[0].confirmed);
}

// An object seen through (the depth far behind where it was) in kObjectMissingViews
// keyframes in a row was carried away; a person in front of it (depth nearer) or a
// view elsewhere says nothing.
TEST(ObjectDatabase, RemovesAnObjectSeenMissingWhereItWas) {
  ObjectDatabase db = MakeDatabase();
  const auto box = BoxSurface({0, 0, 2.0}, {0.4, 0.4, 0.4});
  const int id = db.Add(View("suitcase", 28, box, Turned(0)), Turned(0));
  const cv::Mat wall = DepthPlane(3.5), person = DepthPlane(1.0);
  EXPECT_EQ(db.CountViews({}, Turned(0), wall, 5000), 0);
  EXPECT_EQ(db.CountViews({}, Turned(0), person, 5000), 0);  // occluded: the count goes on
  EXPECT_EQ(db.CountViews({}, Turned(90), wall, 5000), 0);   // out of view
  EXPECT_EQ(db.CountViews({}, Turned(0), wall, 5000), 0);
  EXPECT_EQ(db.CountViews({id}, Turned(0), wall, 5000), 0);  // detected: there after all
  for (int k = 0; k < kObjectMissingViews - 1; ++k) EXPECT_EQ(db.CountViews({}, Turned(0), wall, 5000), 0);
  EXPECT_EQ(db.Estimate(Identity).size(), 1u);
  EXPECT_EQ(db.CountViews({}, Turned(0), wall, 5000), 1);
  EXPECT_TRUE(db.Estimate(Identity).empty());
}

// Two objects made from wrong poses (one chair, its views 0.6 m apart) become one
// when the poses are corrected (a loop closure moved the keyframe).
TEST(ObjectDatabase, MergesObjectsThatComeToOverlapAfterACorrection) {
  ObjectDatabase db = MakeDatabase();
  const auto chair = BoxSurface({0, 0, 2.5}, {0.5, 0.9, 0.5});
  auto features = std::make_shared<const Features>();
  auto kf1 = std::make_shared<KeyFrame>(1, 1, 0, features, Turned(0).Inverse());
  auto kf2 = std::make_shared<KeyFrame>(2, 2, 0, features, Turned(10).Inverse());
  const int a = db.Add(View("chair", 56, chair, Turned(0), 0.8f, kf1), Turned(0));
  // Drifted: the second keyframe was placed 0.6 m to the side of where it was.
  const SE3 drifted = Turned(10, {0.6, 0, 0});
  const int b = db.Add(View("chair", 56, chair, Turned(10), 0.8f, kf2), drifted);
  EXPECT_NE(a, b);
  EXPECT_EQ(db.objects().size(), 2u);
  db.Refresh([&](const KeyFrame& kf) { return kf.id == 1 ? Turned(0) : Turned(10); });
  ASSERT_EQ(db.objects().size(), 1u);
  EXPECT_EQ(db.objects()[0].id, a);
  EXPECT_EQ(db.objects()[0].observations.size(), 2u);
}

// A view cut by the image border starts an object (it may never be seen whole) that
// is marked incomplete and confirmed from one view more than a whole one; once a
// whole view comes, the cut views' samples (which drag in floor or wall on the cut
// side) no longer shape its box.
TEST(ObjectDatabase, CutViewsStartObjectsButAWholeViewShapesThem) {
  ObjectDatabase db(SemanticConfig(), nullptr, cv::Size(640, 480));  // no carving: the views' own samples
  const auto slab = [](double x0, double x1) {
    std::vector<Eigen::Vector3d> out;
    for (int i = 0; i <= 20; ++i)
      for (int j = 0; j <= 10; ++j) out.emplace_back(x0 + (x1 - x0) * i / 20.0, 0.5 * j / 10.0 - 0.25, 3.0);
    return out;
  };
  const auto cut = [&](double x0, double x1, double yaw) {
    ObjectObservation o = View("sofa", 57, slab(x0, x1), Turned(yaw));
    o.cut = true;
    return o;
  };
  // Three cut views: the part in view, one that took in 0.6 m of the wall beside it.
  const int id = db.Add(cut(0.0, 1.0, 0), Turned(0));
  EXPECT_EQ(db.Add(cut(0.0, 2.4, 6), Turned(6)), id);
  EXPECT_EQ(db.Add(cut(0.0, 1.0, 12), Turned(12)), id);
  auto est = db.Estimate(Identity);
  ASSERT_EQ(est.size(), 1u);
  EXPECT_FALSE(est[0].complete);
  EXPECT_FALSE(est[0].confirmed);  // all cut: one view more than kObjectMinObservations needed
  EXPECT_GT(est[0].size.x(), 2.2);  // only cut views: all of them count
  EXPECT_EQ(db.Add(cut(0.0, 1.0, 3), Turned(3)), id);
  est = db.Estimate(Identity);
  EXPECT_FALSE(est[0].complete);
  EXPECT_TRUE(est[0].confirmed);
  // The whole sofa, 1.8 m, in one view.
  EXPECT_EQ(db.Add(View("sofa", 57, slab(0.0, 1.8), Turned(9)), Turned(9)), id);
  est = db.Estimate(Identity);
  ASSERT_EQ(est.size(), 1u);
  EXPECT_TRUE(est[0].complete);
  EXPECT_TRUE(est[0].exported);
  EXPECT_NEAR(est[0].size.x(), 1.8, 0.05);
  EXPECT_EQ(est[0].observations, 5);
}

TEST(ObjectSizes, RangesFlagBoxesThatTookInTheBackground) {
  EXPECT_TRUE(PlausibleSize("tvmonitor", {0.55, 0.40, 0.06}));
  EXPECT_FALSE(PlausibleSize("tvmonitor", {1.09, 0.89, 0.63}));  // the wall behind it
  EXPECT_FALSE(PlausibleSize("keyboard", {0.9, 0.2, 0.05}));
  EXPECT_FALSE(PlausibleSize("cup", {0.02, 0.02, 0.01}));        // too small to be a whole cup
  EXPECT_TRUE(PlausibleSize("cup", {0.02, 0.02, 0.01}, false));  // but a cut view of one may be
  EXPECT_TRUE(PlausibleSize("a class without a range", {9, 9, 9}));
  EXPECT_TRUE(SizeRangeOf("chair").has_value());
}

}  // namespace
}  // namespace sgslam
