// Configuration of the semantic mapping thread (paper Sec. III-E): the static dense
// cloud, the OctoMap and the database of 3-D semantic objects built from keyframes.
// Defaults: depth range, box shrink and OctoMap sensor model as in the authors'
// release (reference-notes.md); strides and voxel sizes chosen so that a keyframe
// costs tens of milliseconds on one core here.
#pragma once

#include <string>

#include "sgslam/common/config_checker.h"

namespace sgslam {

struct SemanticConfig {
  bool enabled = true;          // build cloud.ply, octomap.bt and objects.json
  int queue_size = 64;          // keyframes waiting for the semantic thread (~1.5 MB each); when full the oldest is dropped
  bool low_priority = true;     // run the semantic thread at the lowest CPU priority (it catches up when tracking idles)
  double depth_min = 0.5;       // m, depths used for the cloud, the OctoMap and objects
  double depth_max = 5.0;       // m
  int cloud_stride = 3;         // px, pixel step when back-projecting a keyframe's depth
  double cloud_voxel = 0.02;    // m, voxel side of the dense cloud (per keyframe and on export)
  // Pixels within this many px of a depth step are left out of the cloud and the
  // OctoMap (cloud.cpp, OnDepthEdge); 0: off. The step: jump + quadratic * depth^2.
  // dyn_dev sg sequential, share of the cloud on moving pixels / exported points /
  // OctoMap path cells occupied: radius 0 1.42 % / 151k / 11.4 %; 2: 1.18 % / 144k
  // / 7.7 %; 4: 1.11 % / 136k / 6.1 % (2 consistency votes). fr1_rpy: 223k
  // points at radius 2 against 233k.
  int cloud_edge_radius = 2;
  double cloud_edge_jump = 0.05;            // m
  double cloud_edge_jump_quadratic = 0.02;  // 1/m
  double box_margin = 0.05;     // share of the box size added on each side of dynamic boxes before masking
  // Dynamic boxes of the frames within box_window of a keyframe are carried into
  // it (box_window.h): the detector misses a person in some frames. 0: off.
  // dyn_dev, sg, sequential, share of the cloud on moving pixels / exported points:
  // window 0: 1.51 % / 173k; 2: 1.20 % / 159k; 4: 1.12 % / 141k; 4 with growth 2 and
  // band 0.25: 1.20 % / 150k (what is left: people cut by the image edge or behind
  // the monitor, which the detector does not find in any frame). With the
  // trajectory of dynamic.max_box_area 0.7: window 0: 1.71 %, 2: 1.43 %, 4: 1.25 %.
  int box_window = 2;                // frames on each side
  double box_window_growth = 4.0;    // px added on each side per frame of distance (the object's own motion)
  double box_window_band = 0.4;      // m, only pixels this close to the carried box's depth are masked
  double box_window_max_area = 0.5;  // share of the image; larger boxes are not carried
  int box_window_history = 600;      // frames of boxes kept for a semantic thread that lags behind
  int motion_radius = 25;       // px, pixels around a rejected keypoint outside boxes that may be masked
  double motion_depth_band = 0.15;  // m, ... when their depth is within this of the keypoint's
  // Moving segments: the depth image cut into smooth connected regions (on a
  // grid of this step); a region where most keypoints were rejected is masked
  // whole (an object the detector does not know moves as one surface).
  bool motion_segments = true;
  int motion_segment_step = 4;                 // px, grid step of the segmentation
  double motion_segment_jump = 0.02;           // m, depth step between grid neighbours that still joins them ...
  double motion_segment_jump_quadratic = 0.02; // 1/m, ... plus this times depth^2
  int motion_segment_min_votes = 3;            // rejected keypoints a region needs
  double motion_segment_min_share = 0.5;       // share of its keypoints that were rejected
  double motion_segment_max_area = 0.5;        // share of the image, larger regions are background (walls, floor)
  // Keypoints kept without a geometric test (no flow pair: a walker entering at the
  // image edge, blur) count neither way in a segment's share: on dyn_dev frames
  // 128-134 a walker cut by the border had 47-82 such keypoints against 9-25
  // rejected and stayed in the map. dyn_dev sg panels (5 ORB budgets, sequential,
  // same trajectories), median cloud on moving pixels 0.46 -> 0.39 % (lower in all
  // five), OctoMap path cells occupied 47 -> 44 (worst 82 -> 64), exported points
  // -0.2 to -0.9 %; fr1_rpy sg 130144 -> 130147 points.
  bool motion_segment_skip_unjudged = true;
  bool free_space_filter = true;    // drop cloud points whose OctoMap voxel ended up free (moved away)
  // Multi-view consistency on export: a cloud point that other keyframes see
  // through (their depth at its pixel is clearly behind it) was something that
  // moved away; it is dropped, and the OctoMap is rebuilt from what remains with
  // the final keyframe poses.
  bool consistency_filter = true;
  double consistency_tolerance = 0.05;            // m, plus the quadratic term below
  double consistency_tolerance_quadratic = 0.01;  // 1/m, times depth^2 (depth noise grows with depth^2)
  // keyframes that must see through a point to drop it. dyn_dev sg sequential,
  // with cloud_edge_radius 2: 1 vote 0.91 % of the cloud on moving pixels, 133k
  // points; 2 votes 1.18 %, 144k. The price on the static fr1_rpy: 202k points
  // against 223k (and 233k with neither this nor the edge test).
  int consistency_min_votes = 1;
  int consistency_pool = 4;                       // px, keyframe depth kept min-pooled by this factor
  // Multi-view support on export: a point stays only when this many keyframes put
  // points within one OctoMap voxel of it; a mover crosses a place in a keyframe
  // or two, a static surface is seen again. 1: off. dyn_dev sg sequential, share
  // of the cloud on moving pixels / OctoMap path cells occupied / exported points:
  // 1: 0.91 % / 6.0 % / 133k; 2: 0.65 % / 2.0 % / 129k; 3: 0.53 % / 0.73 % / 122k;
  // 5: 0.37 % / 0.34 % / 105k. The price on the static fr1_rpy: 181k points at 3
  // against 202k (142k at 5), OctoMap leaves 79k against 95k.
  int min_view_support = 3;
  // Seen moving, on export: a point that other keyframes masked as a mover at the
  // same place (within the consistency tolerance) at least once, and at least
  // seen_moving_ratio times as often as keyframes saw it there unmasked (its own
  // keyframe counts), was a mover the mask missed in its keyframe (a detector miss,
  // a person at the image edge); it is dropped. 0: off. Of a dynamic box only the
  // pixels within seen_moving_band m of its middle's depth count as the mover
  // (dyn_dev, one run, dropping at the first vote: whole boxes took 84 % of the
  // cloud, the 0.4 m band 71 %; with the ratio, 1 and band 0.4: 24 %).
  double seen_moving_ratio = 3.0;
  double seen_moving_band = 0.2;  // m
  // The image border strip (px) is left out of the cloud and the OctoMap: ORB finds
  // no keypoints there, so no motion evidence, and the detector misses the people it
  // cuts (on dyn_dev every OctoMap cell left on the people's paths came from masks
  // that missed a person at the image edge, or from a detector miss). Static
  // surfaces there are seen from the other keyframes.
  // dyn_dev sg panels (5 ORB budgets, sequential, same trajectories), median cloud
  // on moving pixels / OctoMap path cells occupied / exported points; fr1_rpy
  // (static, sg, one run) exported points:
  //   border 0, no seen-moving filter:  0.40 % / 39 (24-63) / 97.8k; fr1_rpy 116.0k
  //   border 24:                        0.18 % / 17 (11-22) / 90.7k; 110.8k
  //   border 32:                        0.14 % /  9 (5-18)  / 86.3k; 107.4k
  //   border 24, seen-moving ratio 3:   0.11 % / 12 (10-21) / 89.1k; 109.2k
  //   border 32, seen-moving ratio 3:   0.08 % /  8 (3-18)  / 84.8k; 105.9k
  // One run (budget 1000), border 24, ratio 1 / 2 / 3 with band 0.2: path cells 7 /
  // 8 / 10, points 67.6k / 76.7k / 81.5k.
  int cloud_border = 32;
  // A second, larger detector run on each keyframe in this thread (a Darknet file
  // stem in detector.model_dir; used only with the dnn backend; empty: off). Its
  // dynamic-class boxes join the keyframe's own in the mask, nothing else: tracking
  // keeps the fast model. Yolo-Fastest 1.1 misses people the XL model finds (on
  // dyn_dev, budget 1000, a walker in 86 against 132 of the 223 frames it is in,
  // by box IoU > 0.3; frames 118-152 at the right image edge nearly throughout),
  // and it is those keyframes whose depth was left on the walkers' paths. A
  // keyframe comes every 3-4 frames, so the XL model's ~22 ms cost the low-priority
  // thread 6 ms of CPU a frame. dyn_dev sg panels (ORB budgets 900-1125, sequential,
  // same trajectories), OctoMap path cells occupied / cloud on moving pixels,
  // medians: off 14 (6-25) / 0.08 %, on 0 (0-12) / 0.04 %. In parallel (4 runs
  // each, alternated): median frame time 25.65 ms against 24.8 ms off and 24.0 ms
  // with no semantic thread; path cells 0, 0, 0 against 13, 12, 20. fr1_rpy: 93k
  // cloud points against 96k. (Tracking with the XL model instead: path cells 0 in
  // 7 of 10 budgets, but ATE median 0.0187 m against 0.0159 and 23 ms of detector
  // against 13 on the tracking path.)
  std::string keyframe_model = "yolo-fastest-1.1-xl";
  // OctoMap (ColorOcTree), sensor model of the release.
  double octomap_resolution = 0.03;  // m
  double octomap_hit = 0.7;          // probability of a hit
  double octomap_miss = 0.4;         // probability of a miss (free ray)
  double octomap_clamp_min = 0.12;   // probability
  double octomap_clamp_max = 0.97;   // probability
  int octomap_stride = 16;           // px, pixel step of the free-space rays cast per keyframe (hits: every cloud point)
  // 3-D semantic objects.
  double object_box_shrink = 0.6;    // share of the box (centred) whose depths form the object
  double object_mad_factor = 3.0;    // depths further than this many MADs from the median are dropped ...
  // ... unless within this share of the box's width (in metres, at the median
  // depth) of it: a flat front face has a MAD of a centimetre and would cut off
  // whatever lies behind it (a pot under its leaves, a chair's seat behind its
  // back); an object is about as deep as it is wide, and the background behind
  // it goes with the planes and the carving below. Objects preset, seeds 1-6:
  // centroids within 5 cm 16 -> 23 of 40, sizes within 10 cm 22 -> 28 (0.5: 19 / 26,
  // 0.75: 22 / 28, 1.5 and 2: as 1). 0: the MAD band alone.
  double object_depth_band_width = 1.0;
  int object_min_points = 30;        // depth samples needed for an observation
  int object_max_points = 400;       // samples kept per observation (anchored to its keyframe)
  double object_min_score = 0.3;     // detections below this score are not used for objects
  double object_merge_iou = 0.1;     // 3-D IoU above which an observation joins an object of its class
  double object_merge_margin = 0.1;  // m, association boxes are grown by this for the centre-inside test
  int object_border = 3;             // px, a box this close to the image edge is cut off (its samples count only until a whole view comes)
  // Share of the samples cut off at each end of each axis of an object's extent
  // (outliers the carving left). A thin leg or a pot's base is a small share of
  // the samples: objects preset seeds 1-6, 0.02 -> 0.01: centroids within 5 cm
  // 27 -> 31 of 40, sizes within 10 cm 28 -> 34, worst centroid 0.13 -> 0.12 m,
  // worst size 0.23 -> 0.20 m (0.005: 32 / 32, but worst 0.18 / 0.33 m).
  double object_extent_trim = 0.01;
  int object_min_observations = 2;   // objects seen fewer times are not exported (one view is too little evidence)
  // Background planes: floor and walls fitted in a ring around the box and
  // removed inside it (they sit at the object's depth, so the depth band keeps them).
  // planes fitted per box; 0 turns the step off. 3: floor and both walls of a
  // corner (objects preset, seeds 1-6: worst centroid error 0.54 -> 0.24 m with
  // 3 planes and PlaneFitOptions::min_share 0.12, from 2 and 0.25)
  int object_background_planes = 3;
  // Ring width as a share of the box size (at least 6 px). A wide ring holds
  // enough of both walls of a corner for each to make a plane: seeds 1-6 (with
  // the width band above), 0.15 -> 0.3: centroids within 5 cm 23 -> 27 of 40,
  // sizes within 10 cm 28 -> 28, worst centroid 0.23 -> 0.13 m, worst size
  // 0.35 -> 0.23 m (a chair in a corner took the walls behind it in). 0.4 and
  // 0.5 gave 27 / 30 and 27 / 29, but at 0.4 dyn_dev's laptop took in another
  // view and grew from 1.1 x 0.8 to 1.9 x 2.2 m; at 0.3 its objects stay within 4 cm.
  double object_ring = 0.3;
  double object_plane_tolerance = 0.01;   // m, distance to a plane counted as on it ...
  double object_plane_tolerance_quadratic = 0.002;  // 1/m, ... plus this times the box depth^2 (Kinect noise ~ depth^2: 2-3 sigma)
  double object_plane_max_share = 0.8;    // a plane holding more of the box points is the object's own face: kept

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
    v("cloud_edge_jump", cloud_edge_jump, "m, depth step of that test");
    v("cloud_edge_jump_quadratic", cloud_edge_jump_quadratic, "1/m, extra depth step times depth^2");
    v("box_margin", box_margin, "share of box size added around dynamic boxes");
    v("box_window", box_window, "frames on each side whose dynamic boxes also mask a keyframe; 0: off");
    v("box_window_growth", box_window_growth, "px per frame of distance added around carried boxes");
    v("box_window_band", box_window_band, "m, depth band around a carried box's depth that is masked");
    v("box_window_max_area", box_window_max_area, "image share above which a box is not carried");
    v("box_window_history", box_window_history, "frames of dynamic boxes kept for the semantic thread");
    v("motion_radius", motion_radius, "px, mask radius around rejected keypoints outside boxes");
    v("motion_depth_band", motion_depth_band, "m, depth band of that mask");
    v("motion_segments", motion_segments, "mask depth segments where most keypoints were rejected");
    v("motion_segment_step", motion_segment_step, "px, grid step of the depth segmentation");
    v("motion_segment_jump", motion_segment_jump, "m, depth step joining grid neighbours");
    v("motion_segment_jump_quadratic", motion_segment_jump_quadratic, "1/m, extra depth step times depth^2");
    v("motion_segment_min_votes", motion_segment_min_votes, "rejected keypoints to mask a segment");
    v("motion_segment_min_share", motion_segment_min_share, "share of rejected keypoints to mask a segment");
    v("motion_segment_skip_unjudged", motion_segment_skip_unjudged, "keypoints kept untested do not count in a segment's share");
    v("motion_segment_max_area", motion_segment_max_area, "image share above which a segment is background");
    v("free_space_filter", free_space_filter, "drop cloud points in voxels the OctoMap saw free");
    v("consistency_filter", consistency_filter, "drop cloud points other keyframes see through; rebuild the OctoMap");
    v("consistency_tolerance", consistency_tolerance, "m, depth margin of the see-through test");
    v("consistency_tolerance_quadratic", consistency_tolerance_quadratic, "1/m, extra margin times depth^2");
    v("consistency_min_votes", consistency_min_votes, "keyframes seeing through a point to drop it");
    v("consistency_pool", consistency_pool, "px, min-pooling factor of the kept keyframe depth");
    v("cloud_border", cloud_border, "px, image border left out of the cloud and the OctoMap");
    v("keyframe_model", keyframe_model, "Darknet model run again on keyframes for the dynamic mask (dnn backend); empty: off");
    v("seen_moving_ratio", seen_moving_ratio, "drop points masked moving this many times as often as seen; 0: off");
    v("seen_moving_band", seen_moving_band, "m, depth layer of a dynamic box that counts as the mover");
    v("min_view_support", min_view_support, "keyframes that must see a point's neighbourhood to keep it; 1: off");
    v("octomap_resolution", octomap_resolution, "m, OctoMap voxel side");
    v("octomap_hit", octomap_hit, "probability of a hit");
    v("octomap_miss", octomap_miss, "probability of a miss");
    v("octomap_clamp_min", octomap_clamp_min, "probability");
    v("octomap_clamp_max", octomap_clamp_max, "probability");
    v("octomap_stride", octomap_stride, "px, pixel step of inserted rays");
    v("object_box_shrink", object_box_shrink, "share of the box used for objects");
    v("object_mad_factor", object_mad_factor, "depth outlier limit in MADs");
    v("object_depth_band_width", object_depth_band_width, "depth outlier limit at least this share of the box width");
    v("object_min_points", object_min_points, "depth samples for an observation");
    v("object_max_points", object_max_points, "samples kept per observation");
    v("object_min_score", object_min_score, "detection score for objects");
    v("object_merge_iou", object_merge_iou, "3-D IoU to merge an observation");
    v("object_merge_margin", object_merge_margin, "m, association box growth");
    v("object_border", object_border, "px, boxes this close to the edge are cut off views");
    v("object_extent_trim", object_extent_trim, "share of samples cut at each end of an object's extent");
    v("object_min_observations", object_min_observations, "observations to export an object");
    v("object_background_planes", object_background_planes, "background planes removed per box (0: off)");
    v("object_ring", object_ring, "ring around the box for background planes, share of box size");
    v("object_plane_tolerance", object_plane_tolerance, "m, on-plane distance");
    v("object_plane_tolerance_quadratic", object_plane_tolerance_quadratic, "1/m, extra on-plane distance times depth^2");
    v("object_plane_max_share", object_plane_max_share, "a plane with more of the box points is kept");
  }
  void Validate(ConfigChecker& c) const;
};

}  // namespace sgslam
