// Configuration of the semantic mapping thread (paper Sec. III-E): the static dense
// cloud, the OctoMap and the database of 3-D semantic objects built from keyframes.
// The keys are what a user sets: whether the thread runs and how, the depth range,
// the resolutions and the keyframe detector. The filters that keep movers out of
// the map are switches (semantic.filters), each measured on its own in
// docs/results-archive.md ("Semantic map"); their sizes and every other value
// (strides, margins, tolerances, the OctoMap sensor model, the object steps) are
// named constants beside their use, with their unit and reason:
//  - cloud.h: kDepthEdgeRadius;
//  - dynamic_mask.h: kBoxMargin, kMotionRadius, kSegmentSkipUnjudged (DynamicMaskOptions);
//  - semantic_mapper.cpp: kBoxWindow;
//  - semantic_map.h: kImageBorder, kMinViewSupport, kSeenMovingRatio (SemanticMapOptions);
//  - semantic_map.cpp: kCloudStride, kConsistencyTolerance, kConsistencyMinVotes,
//    kObjectMinScore;
//  - octomap_builder.cpp: kOctoMapProbHit, kOctoMapProbMiss, kOctoMapClampMin/Max;
//  - objects.h / .cpp: kObjectMinPoints, kObjectMinObservations,
//    kObjectMinSpreadDeg, kObjectMinSeenShare, kObjectMissingViews,
//    kObjectDepthBandWidth, kObjectBackgroundPlanes (ObserveObjectOptions),
//    kObjectBoxShrink, kObjectMergeIou and the association's constants;
//  - object_sizes.cpp: each class's size range.
#pragma once

#include <string>

#include "sgslam/common/config_checker.h"

namespace sgslam {

// The filters that keep movers (people, things carried away) out of the static
// cloud and the OctoMap, each on by default and switchable on its own.
struct SemanticFilters {
  // Pixels within kDepthEdgeRadius (2 px) of a depth step stay out of the cloud and
  // the OctoMap (cloud.cpp): there mask and depth disagree by a pixel or two, and
  // the depth mixes two surfaces.
  bool depth_edges = true;
  // The kImageBorder (32 px) strip at the image border stays out of the cloud and
  // the OctoMap: ORB finds no keypoints there, so no motion evidence, and the
  // detector misses the people it cuts. Static surfaces there are seen from other
  // keyframes.
  bool image_border = true;
  // The dynamic boxes of the kBoxWindow (2) frames on each side of a keyframe are
  // carried into its mask (box_window.h): the detector misses a person in some frames.
  bool box_window = true;
  // Moving segments: the depth image cut into smooth connected regions; a region
  // where most keypoints were rejected is masked whole (an object the detector does
  // not know moves as one surface).
  bool motion_segments = true;
  // On export, a cloud point that other keyframes see through (their depth at its
  // pixel is clearly behind it) was something that moved away; it is dropped, and
  // the OctoMap is rebuilt from what remains with the final keyframe poses.
  bool see_through = true;
  // On export, a point that other keyframes masked as a mover at its place at least
  // kSeenMovingRatio (3) times as often as they saw it there unmasked was a mover
  // its own keyframe's mask missed; it is dropped.
  bool seen_moving = true;
  // On export, a point stays only when kMinViewSupport (3) keyframes put points
  // within one OctoMap voxel of it: a mover crosses a place in a keyframe or two, a
  // static surface is seen again.
  bool view_support = true;
  // On export, a cloud point whose OctoMap voxel ended up free (later views saw
  // through it: it moved away) is dropped.
  bool free_space = true;

  template <class V>
  void Visit(V&& v) {
    v("depth_edges", depth_edges, "leave pixels within 2 px of a depth step out of the cloud and the OctoMap");
    v("image_border", image_border, "leave the 32 px image border out of the cloud and the OctoMap");
    v("box_window", box_window, "the dynamic boxes of the 2 frames on each side also mask a keyframe");
    v("motion_segments", motion_segments, "mask depth segments where most keypoints were rejected");
    v("see_through", see_through, "drop cloud points other keyframes see through; rebuild the OctoMap");
    v("seen_moving", seen_moving, "drop points other keyframes masked as a mover 3 times as often as seen");
    v("view_support", view_support, "keep only points whose neighbourhood 3 keyframes saw");
    v("free_space", free_space, "drop cloud points in voxels the OctoMap saw free");
  }
};

struct SemanticConfig {
  bool enabled = true;       // build cloud.ply, octomap.bt and objects.json
  int queue_size = 64;       // keyframes waiting for the semantic thread (~1.5 MB each); when full the oldest is dropped
  bool low_priority = true;  // run the semantic thread at the lowest CPU priority (it catches up when tracking idles)
  double depth_min = 0.5;    // m, depths used for the cloud, the OctoMap and objects
  double depth_max = 5.0;    // m
  double cloud_voxel = 0.02;  // m, voxel side of the dense cloud (per keyframe and on export)
  double octomap_resolution = 0.03;  // m, OctoMap (ColorOcTree) voxel side
  // A second, larger detector run in this thread on the keyframes with a new view
  // (turned 5 degrees or moved 0.10 m from the last it ran on: SemanticMap::NewView)
  // (a Darknet file stem in detector.model_dir; used only with the dnn backend;
  // empty: off). Its dynamic-class boxes join the keyframe's own in the mask, and
  // its boxes give the objects, which count their views on those keyframes alone:
  // tracking keeps the fast model, the map gets the people the fast one misses and
  // the better-named objects.
  std::string keyframe_model = "yolo-fastest-1.1-xl";
  // objects.json also lists the candidates, in a list of their own: objects not
  // confirmed yet (too few views, too little viewpoint change, seen too rarely when
  // in view) or of a size their class cannot have (docs/object-map.md).
  bool object_candidates = false;
  SemanticFilters filters;  // the filters that keep movers out of the map

  template <class V>
  void Visit(V&& v) {
    v("enabled", enabled, "build cloud, OctoMap and objects");
    v("queue_size", queue_size, "keyframes queued for the semantic thread");
    v("low_priority", low_priority, "lowest CPU priority for the semantic thread");
    v("depth_min", depth_min, "m, valid depth range");
    v("depth_max", depth_max, "m, valid depth range");
    v("cloud_voxel", cloud_voxel, "m, dense cloud voxel side");
    v("octomap_resolution", octomap_resolution, "m, OctoMap voxel side");
    v("keyframe_model", keyframe_model,
      "Darknet model run again on keyframes with a new view (5 deg, 0.10 m) for the mask and the objects (dnn backend); empty: off");
    v("object_candidates", object_candidates, "objects.json also lists the unconfirmed or implausible objects");
    v("filters", filters, "the filters that keep movers out of the cloud and the OctoMap, each switchable");
  }
  void Validate(ConfigChecker& c) const;
};

}  // namespace sgslam
