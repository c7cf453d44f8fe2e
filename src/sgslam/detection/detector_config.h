// Configuration of the object detection thread (paper Sec. III-B) and the class
// table of prior dynamic weights w in 1..5 that Algorithm 1 multiplies the epipolar
// distance with (Sec. III-D: "person w = 5, chair w = 2").
#pragma once

#include <map>
#include <string>

#include "sgslam/common/config_checker.h"

namespace sgslam {

// COCO name (as in coco.names) -> prior dynamic weight w; see detector_config.cpp.
std::map<std::string, double> DefaultDynamicWeights();

struct DetectorConfig {
  std::string backend = "dnn";             // dnn: OpenCV dnn network | file: replay a detections file | none
  std::string model_dir;                   // folder with <model>.cfg/.weights and coco.names; empty: $SGSLAM_MODEL_DIR, else the models shipped with sgslam
  std::string model = "yolo-fastest-1.1";  // Darknet file stem: yolo-fastest-1.1 | yolo-fastest-1.1-xl
  int input_size = 320;                    // px, network input side (the models were trained at 320)
  double score_threshold = 0.4;            // objectness * class probability, classes other than person
  double person_score_threshold = 0.15;    // same for person: a missed person costs more than a false one
  int threads = 1;                  // OpenCV threads of the whole process (cv::setNumThreads); 0: OpenCV's default
  int timeout_ms = 100;             // ms tracking waits for the frame's detections (inference: 10-20 ms here)
  // The detector runs on every stride-th frame; the frames between take the last
  // boxes moved with the flow of the keypoints inside them (NGD-SLAM's idea) and
  // the mover tracks' predicted boxes (dynamic.refinements.track_footprints).
  int stride = 1;
  std::string detections_file;      // backend file; empty: <dataset>/detections.txt
  // A table given in YAML replaces the whole default table; classes not in it weigh 1.
  std::map<std::string, double> dynamic_weight = DefaultDynamicWeights();

  template <class V>
  void Visit(V&& v) {
    v("backend", backend, "dnn | file | none");
    v("model_dir", model_dir, "folder of the Darknet model; empty: $SGSLAM_MODEL_DIR, else the shipped models");
    v("model", model, "yolo-fastest-1.1 | yolo-fastest-1.1-xl");
    v("input_size", input_size, "px, network input side, multiple of 32");
    v("score_threshold", score_threshold, "objectness * class probability, non-person classes");
    v("person_score_threshold", person_score_threshold, "objectness * class probability, person");
    v("threads", threads, "OpenCV threads of the process; 0: OpenCV default");
    v("timeout_ms", timeout_ms, "ms tracking waits for the frame's detections");
    v("stride", stride, "run the detector on every Nth frame; between, its boxes follow the flow");
    v("detections_file", detections_file, "backend file; empty: <dataset>/detections.txt");
    v("dynamic_weight", dynamic_weight, "class name: prior dynamic weight w in 1..5 (Algorithm 1)");
  }
  void Validate(ConfigChecker& c) const;
};

// Read-only view of the class table, shared by tracking and semantic mapping.
// weight(): w of Algorithm 1 for a point inside a box of that class; 1 (the static
// test) for classes the table does not know. is_dynamic(): the class is a moving
// object (w >= kMinWeight, 3: a thing carried or worn and up): its boxes are left out of the fundamental-matrix
// sample and of the semantic map (Sec. III-E: "except dynamic objects, e.g., people,
// and dogs"). A chair (w = 2) is thus weighted in Algorithm 1 but stays a static
// map object, which is how the paper treats it (Sec. II-A: static by default).
class ClassTable {
 public:
  static constexpr double kMinWeight = 3.0;  // classes with w >= this are moving objects

  explicit ClassTable(const DetectorConfig& config) : weights_(config.dynamic_weight) {}

  double weight(const std::string& class_name) const {
    const auto it = weights_.find(class_name);
    return it == weights_.end() ? 1.0 : it->second;
  }
  bool is_dynamic(const std::string& class_name) const { return weight(class_name) >= kMinWeight; }

 private:
  std::map<std::string, double> weights_;
};

}  // namespace sgslam
