// Scores a run's object map against a list of the sequence's true objects: the
// synthetic presets' objects_gt.json (sgslam synth: exact boxes) or a hand-made
// list of a real room (tests/data/tum_fr1_rpy_objects.json: approximate centres
// and sizes, made by looking at the frames; docs/object-map.md). Both give, per
// object, "class", "centroid" and "size" (m, axis-aligned in the ground truth's
// world); optional "dynamic" (a mover: not a map object), "static": false (the
// same), and "coco": false (a class the detector does not know: an estimate on it
// is neither right nor wrong, and it is not missed). A mover without a centroid
// (sgslam synth's walkers) is left out.
//
// The estimates, in the same world (the run's ATE alignment), are matched to the
// true objects one to one, nearest first (a different class costs kClassPenalty
// metres), within a gate: the centre inside the true box grown by kGateMargin, or
// within kGateDistance of its centre. A further estimate within the gate of a
// matched object is a duplicate; one within none is a false positive.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "sgslam/semantic/objects.h"

namespace sgslam::eval {

struct TrueObject {
  int id = 0;
  std::string class_name;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  // m, world
  Eigen::Vector3d size = Eigen::Vector3d::Zero();      // m, axis-aligned in the world
  bool scored = true;  // static and of a class the detector knows
};

// Throws InputError naming the file and the object for a malformed list.
std::vector<TrueObject> LoadObjectTruth(const std::filesystem::path& path);

struct ObjectMatch {
  int estimate_id = 0;
  std::string estimate_class;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero(), size = Eigen::Vector3d::Zero();  // world
  int truth_id = 0;  // 0: none
  enum Kind { kMatched, kDuplicate, kFalse, kUnscored } kind = kFalse;
  double centroid_error = 0;  // m, when matched or a duplicate
  double size_error = 0;      // |size - true size| / |true size|, when matched
};

struct ObjectScore {
  int estimates = 0, truths = 0;  // estimates given; true objects scored
  int matched = 0, duplicates = 0, false_positives = 0, unscored = 0, correct_class = 0;
  double precision = 0;  // matched / (matched + duplicates + false positives)
  double recall = 0;     // matched / truths
  double class_accuracy = 0;
  double median_centroid_error = 0, median_size_error = 0;
  std::vector<ObjectMatch> matches;  // one per estimate
  std::vector<int> missed;           // the scored true objects no estimate matched
};

// estimates: exported objects only, in the truth's world.
ObjectScore ScoreObjects(const std::vector<TrueObject>& truth, const std::vector<ObjectEstimate>& estimates);

nlohmann::json ToJson(const ObjectScore& score);

}  // namespace sgslam::eval
