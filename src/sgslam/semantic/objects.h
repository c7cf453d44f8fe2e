// 3-D semantic objects from 2-D detections and depth (paper Sec. III-E): for every
// detection of a static class in a keyframe, the box is shrunk towards its centre
// (kObjectBoxShrink), depths far from the median (in MADs, at least
// kObjectDepthBandWidth of the box's width) are dropped, background planes fitted
// around the box are removed inside it (kObjectBackgroundPlanes), pixels where
// another box of the frame overlaps and whose depth is nearer that box's object go
// to it (occlusion: the paper does not say), movers' pixels are left out, 3-D
// outliers are removed, and the samples are kept in the keyframe's camera frame.
// The database associates an observation in 3-D whatever its label (shared voxels
// and box overlap; another class needs much more overlap than the object's own),
// keeps every observation's class and score for a vote (WinningClass), and merges
// objects that come to overlap when the keyframes' poses change (Refresh). A box
// cut by the image edge is a partial view: it may start an object (a sofa next to
// the camera may never be seen whole), but its samples shape the object only until
// a whole view comes, and an object seen only cut is marked complete = false and
// needs one view more to be confirmed. An object is believed (confirmed) from the
// evidence of its views: kObjectMinObservations keyframes, kObjectMinSpreadDeg of
// viewpoint change, detected in kObjectMinSeenShare of the keyframes it was in view
// of (CountViews); it is removed once seen missing where it was. Each object keeps
// its observations anchored to their keyframes: its centroid and size are
// recomputed from them with the keyframes' current poses (robust: 1st-99th
// percentile extents of the samples that the other views' boxes agree with, see
// CarvedPoints), so bundle adjustment moves objects with the map.
// docs/object-map.md describes the whole.
//
// Threading: not thread-safe; the semantic mapping thread owns the database.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "sgslam/common/se3.h"
#include "sgslam/detection/detection.h"
#include "sgslam/semantic/cloud.h"
#include "sgslam/semantic/semantic_config.h"

namespace sgslam {

// Depth samples kept per object observation (each is anchored to its keyframe).
inline constexpr int kObjectMaxPoints = 400;
// Depth samples an observation needs (in its inner box, and left at the end): fewer
// is a sliver of the object, too little for a median and a MAD.
inline constexpr int kObjectMinPoints = 30;
// Share of the box's width (in metres at the object's median depth) within which a
// depth belongs to the object even beyond 3 MADs of the median: a flat front face
// has a MAD of a centimetre and would cut off whatever lies behind it (a pot under
// its leaves, a chair's seat behind its back), and an object is about as deep as it
// is wide (objects preset, seeds 1-6: centroids within 5 cm 16 -> 23 of 40;
// docs/results-archive.md).
inline constexpr double kObjectDepthBandWidth = 1.0;
// Background planes fitted in a ring around a box and removed inside it (they sit
// at the object's depth, so the depth band keeps them): floor and both walls of a
// corner (with two the worst errors were 0.54 m and 0.90 m).
inline constexpr int kObjectBackgroundPlanes = 3;

// The segmentation's parameters: the pipeline passes the constants; tests turn a
// step off to see what it does.
struct ObserveObjectOptions {
  double depth_band_width = kObjectDepthBandWidth;  // share of the box's width; 0: the MAD band alone
  int background_planes = kObjectBackgroundPlanes;  // 0: none removed
};

class KeyFrame;

struct ObjectObservation {
  std::shared_ptr<KeyFrame> keyframe;     // anchor (null: the pose given to Add stays the pose)
  int class_id = -1;
  std::string class_name;
  float score = 0.f;
  cv::Rect2f box;                         // px, the detection box (raw image)
  SE3 T_w_c_added;                        // the keyframe's pose when added (set by Add; the pose without a keyframe)
  std::vector<Eigen::Vector3f> points_c;  // m, samples in the keyframe's camera frame
  bool cut = false;                       // the box touches the image border: part of the object is out of view
};

// Camera-frame point -> raw (distorted) pixel, for checking boxes across views.
using ProjectFn = std::function<Eigen::Vector2d(const Eigen::Vector3d& p_c)>;

// Another detection of the same frame and the depth of its object: where the two
// boxes overlap, a pixel nearer that depth than this object's belongs to the other
// object (an occluder in front of this one, or an object behind it).
struct OtherBox {
  cv::Rect2f box;
  double depth = 0;  // m; 0: unknown, the box is ignored
};

// The object depth of every detection of a frame: the median depth over the inner
// kObjectBoxShrink of its box, leaving out pixels that other boxes cover (the
// occluder would otherwise set the depth of a half-hidden object); over the whole
// inner box when the others cover nearly all of it. 0 where no depth is valid.
std::vector<double> ObjectDepths(const std::vector<Detection>& detections, const cv::Mat& depth_raw,
                                 double depth_factor, const SemanticConfig& config);

// The observation a detection gives, or none with too few valid depth samples.
// `others`: the frame's other boxes (see OtherBox), none by default. `movers`: the
// keyframe's mask of moving pixels (CV_8U, non-zero: a mover; empty: none), whose
// samples are left out; none when most of the box's samples are on movers.
std::optional<ObjectObservation> ObserveObject(const Detection& detection, const cv::Mat& depth_raw,
                                               double depth_factor, const PixelRays& rays,
                                               const SemanticConfig& config, const std::vector<OtherBox>& others = {},
                                               const cv::Mat& movers = cv::Mat(),
                                               const ObserveObjectOptions& options = {});

struct ObjectEstimate {
  int id = 0;
  int class_id = -1;
  std::string class_name;   // the class with the largest summed detection score
  double class_share = 1;   // that class's share of the summed scores of every class
  double confidence = 0;    // mean score * (1 - exp(-observations / 2)): grows with consistent views
  int observations = 0;     // keyframes whose detections joined the object
  int views_expected = 0;   // keyframes it was in view of, unoccluded, since it was started
  int views_seen = 0;       // of those, the ones whose detection joined it
  int points = 0;           // samples its box was estimated from
  double spread_deg = 0;    // viewpoint change over the keyframes that saw it
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  // m, centre of the box, output frame
  Eigen::Vector3d size = Eigen::Vector3d::Zero();      // m, axis-aligned extent in the output frame
  Eigen::Vector3d dimensions = Eigen::Vector3d::Zero();  // m, extents along its principal axes, longest first
  bool confirmed = false;   // seen often, from far enough apart and often enough when in view (ConfirmedBy)
  bool plausible = true;    // dimensions within its class's size range (object_sizes.h)
  bool exported = false;    // listed in objects.json: confirmed and plausible
  bool complete = true;     // seen whole at least once; false: every view was cut by the image border,
                            // so centroid and size cover only the part in view
};

// T_w_c of a keyframe now (the caller resolves culled keyframes and locking).
using KeyFramePoseFn = std::function<SE3(const KeyFrame&)>;

// The evidence an object needs to be believed: observations from this many
// keyframes (one more when every view was cut by the image border: it is weaker
// evidence)...
inline constexpr int kObjectMinObservations = 3;
// ... whose views of it differ by at least this angle (the object's direction in
// the camera, or the cameras' baseline seen from it: a detector's mistake repeats
// in near-identical images, not from another place)...
inline constexpr double kObjectMinSpreadDeg = 10.0;
// ... and that saw it in at least this share of the keyframes it was in view of,
// unoccluded (a false detection comes and goes; a real object is seen again).
inline constexpr double kObjectMinSeenShare = 0.25;
// An object is removed when this many keyframes in a row see through the place it
// was (depth well behind its points), none of them detecting it: it was carried away.
inline constexpr int kObjectMissingViews = 3;

class ObjectDatabase {
 public:
  // project / image: the camera, for carving and for the views' bookkeeping.
  ObjectDatabase(const SemanticConfig& config, ProjectFn project, cv::Size image)
      : config_(config), project_(std::move(project)), image_(image) {}

  // Moves every object's association geometry to the keyframes' current poses
  // (bundle adjustment, loop corrections) and merges the objects that have come to
  // overlap. Call before adding a keyframe's observations.
  void Refresh(const KeyFramePoseFn& pose_of);
  // Places the observation with the keyframe's pose T_w_c and associates it in 3-D
  // (Associate); returns the object's id.
  int Add(ObjectObservation observation, const SE3& T_w_c);
  // After a keyframe's observations: every object whose points fall in its image is
  // checked against its depth (ViewOf). In view and unoccluded: expected, and seen
  // when one of `joined` (the ids Add returned for this keyframe). Seen through:
  // missing, and removed after kObjectMissingViews such keyframes in a row. An
  // object partly on `movers` (the keyframe's moving pixels, CV_8U; may be empty)
  // is not judged: a person over or beside it hides it from the detector. Returns
  // how many objects were removed.
  int CountViews(const std::vector<int>& joined, const SE3& T_w_c, const cv::Mat& depth_raw, double depth_factor,
                 const cv::Mat& movers = cv::Mat());
  // Every object, re-estimated with the keyframes' current poses, in the frame
  // T_out_w * world (identity: the map frame).
  std::vector<ObjectEstimate> Estimate(const KeyFramePoseFn& pose_of, const SE3& T_out_w = SE3()) const;

  struct Box {
    Eigen::Vector3d min, max;
  };
  struct Object {
    int id = 0;
    std::vector<ObjectObservation> observations;
    int views_expected = 0, views_seen = 0;
    int missing = 0;  // keyframes in a row that saw through it
    // Association only (not saved): the observations' samples at the poses last
    // refreshed, their voxels (kAssociationVoxel) and their percentile box.
    std::vector<SE3> T_w_c;
    std::vector<Eigen::Vector3d> points_w;
    std::vector<std::int64_t> voxels;  // sorted, unique
    Box box{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  };
  // What the database holds, for saving a map (mapfile/), and restoring it into an
  // empty database (the association geometry is rebuilt from the observations).
  const std::vector<Object>& objects() const { return objects_; }
  int next_id() const { return next_id_; }
  void Restore(std::vector<Object> objects, int next_id);

  // The class histogram's winner (summed scores) and its share.
  struct ClassVote {
    int class_id = -1;
    std::string class_name;
    double share = 0;
  };
  static ClassVote WinningClass(const Object& o);

 private:
  // Percentile extents (a trimmed share cut off at each end of each axis).
  static Box BoxOf(const std::vector<Eigen::Vector3d>& points);
  // The object's samples in the world frame (T_w_c: per observation) that the other views agree with: a
  // sample is kept when, among the other observations whose image it projects
  // into, at least half have it inside their box (a visual hull of the boxes: the
  // floor and wall caught in one view's box corners fall outside the others').
  // Cut views' samples are left out when the object has a whole view.
  std::vector<Eigen::Vector3d> CarvedPoints(const Object& o, const std::vector<SE3>& T_w_c) const;
  // Seen whole (not cut by the image border) at least once.
  static bool Complete(const Object& o);
  // The association geometry from the observations at o.T_w_c.
  void Rebuild(Object& o) const;
  // The best object for an observation's world samples and class, or null: see Associate in objects.cpp.
  Object* Associate(const std::vector<std::int64_t>& voxels, const Box& box, const ObjectObservation& observation);
  // Merges every pair of objects whose samples now overlap (MergeRule).
  void MergeOverlapping();

  SemanticConfig config_;
  ProjectFn project_;
  cv::Size image_;
  std::vector<Object> objects_;
  int next_id_ = 1;
};

}  // namespace sgslam
