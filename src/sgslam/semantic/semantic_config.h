// Configuration of the semantic mapping thread (paper Sec. III-E): the static dense
// cloud, the OctoMap and the database of 3-D semantic objects built from keyframes.
// Defaults: depth range, box shrink and OctoMap sensor model as in the authors'
// release; strides and voxel sizes chosen so that a keyframe
// costs tens of milliseconds on one core. The filters that keep movers out of the
// map are described in docs/results-archive.md with their measurements.
#pragma once

#include <string>

#include "sgslam/common/config_checker.h"

namespace sgslam {

struct SemanticConfig {
  bool enabled = true;       // build cloud.ply, octomap.bt and objects.json
  int queue_size = 64;       // keyframes waiting for the semantic thread (~1.5 MB each); when full the oldest is dropped
  bool low_priority = true;  // run the semantic thread at the lowest CPU priority (it catches up when tracking idles)
  double depth_min = 0.5;    // m, depths used for the cloud, the OctoMap and objects
  double depth_max = 5.0;    // m
  int cloud_stride = 3;      // px, pixel step when back-projecting a keyframe's depth
  double cloud_voxel = 0.02;  // m, voxel side of the dense cloud (per keyframe and on export)
  // px; pixels this close to a depth step are left out of the cloud and the
  // OctoMap (cloud.cpp): there mask and depth disagree by a pixel or two, and the
  // depth mixes two surfaces. 0: off.
  int cloud_edge_radius = 2;
  double box_margin = 0.05;  // share of the box size added on each side of dynamic boxes before masking
  // Frames on each side of a keyframe whose dynamic boxes are carried into it
  // (box_window.h): the detector misses a person in some frames. 0: off.
  int box_window = 2;
  int motion_radius = 25;  // px, pixels around a rejected keypoint outside boxes that may be masked
  // Moving segments: the depth image cut into smooth connected regions; a region
  // where most keypoints were rejected is masked whole (an object the detector does
  // not know moves as one surface).
  bool motion_segments = true;
  // Keypoints kept without a geometric test (no flow pair: a walker entering at the
  // image edge, blur) count neither way in a segment's share.
  bool motion_segment_skip_unjudged = true;
  bool free_space_filter = true;  // drop cloud points whose OctoMap voxel ended up free (moved away)
  // Multi-view consistency on export: a cloud point that other keyframes see
  // through (their depth at its pixel is clearly behind it) was something that
  // moved away; it is dropped, and the OctoMap is rebuilt from what remains with
  // the final keyframe poses.
  bool consistency_filter = true;
  double consistency_tolerance = 0.05;  // m, plus a term that grows with depth^2 (semantic_mapper.cpp)
  int consistency_min_votes = 1;        // keyframes that must see through a point to drop it
  // Multi-view support on export: a point stays only when this many keyframes put
  // points within one OctoMap voxel of it; a mover crosses a place in a keyframe or
  // two, a static surface is seen again. 1: off.
  int min_view_support = 3;
  // Seen moving, on export: a point that other keyframes masked as a mover at its
  // place at least seen_moving_ratio times as often as they saw it there unmasked
  // was a mover its own keyframe's mask missed; it is dropped. 0: off.
  double seen_moving_ratio = 3.0;
  // px; the image border strip is left out of the cloud and the OctoMap: ORB finds
  // no keypoints there, so no motion evidence, and the detector misses the people it
  // cuts. Static surfaces there are seen from other keyframes.
  int cloud_border = 32;
  // A second, larger detector run on each keyframe in this thread (a Darknet file
  // stem in detector.model_dir; used only with the dnn backend; empty: off). Its
  // dynamic-class boxes join the keyframe's own in the mask, nothing else: tracking
  // keeps the fast model, and the map gets the people the fast one misses.
  std::string keyframe_model = "yolo-fastest-1.1-xl";
  // OctoMap (ColorOcTree), sensor model of the release.
  double octomap_resolution = 0.03;  // m
  double octomap_hit = 0.7;          // probability of a hit
  double octomap_miss = 0.4;         // probability of a miss (free ray)
  double octomap_clamp_min = 0.12;   // probability
  double octomap_clamp_max = 0.97;   // probability
  // 3-D semantic objects.
  double object_box_shrink = 0.6;  // share of the box (centred) whose depths form the object
  // Depths further from the object's median than 3 MADs are dropped, unless within
  // this share of the box's width (in metres, at the median depth): a flat front
  // face has a MAD of a centimetre and would cut off whatever lies behind it, and an
  // object is about as deep as it is wide. 0: the MAD band alone.
  double object_depth_band_width = 1.0;
  int object_min_points = 30;        // depth samples needed for an observation
  double object_min_score = 0.3;     // detections below this score are not used for objects
  double object_merge_iou = 0.1;     // 3-D IoU above which an observation joins an object of its class
  int object_min_observations = 2;   // objects seen fewer times are not exported (one view is too little evidence)
  // Background planes fitted in a ring around a box and removed inside it (they sit
  // at the object's depth, so the depth band keeps them): 3 are floor and both
  // walls of a corner. 0: off.
  int object_background_planes = 3;

  template <class V>
  void Visit(V&& v) {
    v("enabled", enabled, "build cloud, OctoMap and objects");
    v("queue_size", queue_size, "keyframes queued for the semantic thread");
    v("low_priority", low_priority, "lowest CPU priority for the semantic thread");
    v("depth_min", depth_min, "m, valid depth range");
    v("depth_max", depth_max, "m, valid depth range");
    v("cloud_stride", cloud_stride, "px, back-projection pixel step");
    v("cloud_voxel", cloud_voxel, "m, dense cloud voxel side");
    v("cloud_edge_radius", cloud_edge_radius, "px, pixels this close to a depth step are left out; 0: off");
    v("box_margin", box_margin, "share of box size added around dynamic boxes");
    v("box_window", box_window, "frames on each side whose dynamic boxes also mask a keyframe; 0: off");
    v("motion_radius", motion_radius, "px, mask radius around rejected keypoints outside boxes");
    v("motion_segments", motion_segments, "mask depth segments where most keypoints were rejected");
    v("motion_segment_skip_unjudged", motion_segment_skip_unjudged, "keypoints kept untested do not count in a segment's share");
    v("free_space_filter", free_space_filter, "drop cloud points in voxels the OctoMap saw free");
    v("consistency_filter", consistency_filter, "drop cloud points other keyframes see through; rebuild the OctoMap");
    v("consistency_tolerance", consistency_tolerance, "m, depth margin of the see-through test");
    v("consistency_min_votes", consistency_min_votes, "keyframes seeing through a point to drop it");
    v("cloud_border", cloud_border, "px, image border left out of the cloud and the OctoMap");
    v("keyframe_model", keyframe_model, "Darknet model run again on keyframes for the dynamic mask (dnn backend); empty: off");
    v("seen_moving_ratio", seen_moving_ratio, "drop points masked moving this many times as often as seen; 0: off");
    v("min_view_support", min_view_support, "keyframes that must see a point's neighbourhood to keep it; 1: off");
    v("octomap_resolution", octomap_resolution, "m, OctoMap voxel side");
    v("octomap_hit", octomap_hit, "probability of a hit");
    v("octomap_miss", octomap_miss, "probability of a miss");
    v("octomap_clamp_min", octomap_clamp_min, "probability");
    v("octomap_clamp_max", octomap_clamp_max, "probability");
    v("object_box_shrink", object_box_shrink, "share of the box used for objects");
    v("object_depth_band_width", object_depth_band_width, "depth outlier limit at least this share of the box width");
    v("object_min_points", object_min_points, "depth samples for an observation");
    v("object_min_score", object_min_score, "detection score for objects");
    v("object_merge_iou", object_merge_iou, "3-D IoU to merge an observation");
    v("object_min_observations", object_min_observations, "observations to export an object");
    v("object_background_planes", object_background_planes, "background planes removed per box (0: off)");
  }
  void Validate(ConfigChecker& c) const;
};

}  // namespace sgslam
