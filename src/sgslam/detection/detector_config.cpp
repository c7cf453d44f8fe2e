#include "sgslam/detection/detector_config.h"

#include <string>

namespace sgslam {

// Prior dynamic weights w (paper Sec. III-D): "set according to the probability of
// the object moving", 1..5, person 5 and chair 2 given by the paper. Every name of
// coco.names (Darknet spelling: motorbike, sofa, tvmonitor, ...) is listed so the
// printed configuration shows the whole table. Levels:
//   5  person: moves by itself most of the time, the object the TUM/Bonn walking
//      sequences are about.
//   4  animals and road vehicles: move by themselves, but also rest (a sleeping
//      dog, a parked car) more often than a person walks around.
//   3  things carried or worn by a person (bags, sports gear, phone, tie): they
//      move whenever their owner does. Also bicycles, boats and planes, which are
//      mostly seen parked or moored in the scenes a robot maps.
//   2  small things a person picks up and puts down (tableware, food, books,
//      remote, keyboard, mouse, laptop) and chairs, which get pushed around.
//   1  furniture, appliances, screens, plants, street fixtures: static.
// With ClassTable::kMinWeight = 3, levels 3..5 are moving objects (ClassTable).
std::map<std::string, double> DefaultDynamicWeights() {
  // clang-format off
  return {
      {"person", 5},
      // animals
      {"bird", 4}, {"cat", 4}, {"dog", 4}, {"horse", 4}, {"sheep", 4},
      {"cow", 4}, {"elephant", 4}, {"bear", 4}, {"zebra", 4}, {"giraffe", 4},
      // vehicles
      {"car", 4}, {"motorbike", 4}, {"bus", 4}, {"train", 4}, {"truck", 4},
      {"bicycle", 3}, {"aeroplane", 3}, {"boat", 3},
      // carried or worn
      {"backpack", 3}, {"umbrella", 3}, {"handbag", 3}, {"tie", 3}, {"suitcase", 3},
      {"frisbee", 3}, {"skis", 3}, {"snowboard", 3}, {"sports ball", 3}, {"kite", 3},
      {"baseball bat", 3}, {"baseball glove", 3}, {"skateboard", 3}, {"surfboard", 3},
      {"tennis racket", 3}, {"cell phone", 3},
      // picked up and put down, pushed around
      {"chair", 2}, {"bottle", 2}, {"wine glass", 2}, {"cup", 2}, {"fork", 2},
      {"knife", 2}, {"spoon", 2}, {"bowl", 2}, {"banana", 2}, {"apple", 2},
      {"sandwich", 2}, {"orange", 2}, {"broccoli", 2}, {"carrot", 2}, {"hot dog", 2},
      {"pizza", 2}, {"donut", 2}, {"cake", 2}, {"laptop", 2}, {"mouse", 2},
      {"remote", 2}, {"keyboard", 2}, {"book", 2}, {"scissors", 2}, {"teddy bear", 2},
      {"hair drier", 2}, {"toothbrush", 2},
      // static
      {"traffic light", 1}, {"fire hydrant", 1}, {"stop sign", 1}, {"parking meter", 1},
      {"bench", 1}, {"sofa", 1}, {"pottedplant", 1}, {"bed", 1}, {"diningtable", 1},
      {"toilet", 1}, {"tvmonitor", 1}, {"microwave", 1}, {"oven", 1}, {"toaster", 1},
      {"sink", 1}, {"refrigerator", 1}, {"clock", 1}, {"vase", 1},
  };
  // clang-format on
}

void DetectorConfig::Validate(ConfigChecker& c) const {
  c.Check(backend == "dnn" || backend == "file" || backend == "none", "backend", backend, "must be dnn, file or none");
  // A file stem inside model_dir, not a path: the folder is model_dir's job.
  c.Check(!model.empty() && model.find('/') == std::string::npos, "model", model,
          "must be a model file stem such as yolo-fastest-1.1 or yolo-fastest-1.1-xl");
  // The Yolo-Fastest heads sit at strides 16 and 32.
  c.Check(input_size >= 64 && input_size <= 1024 && input_size % 32 == 0, "input_size", input_size,
          "must be a multiple of 32 in [64, 1024]");
  // 0 would turn every one of the ~120k class scores of a frame into a candidate.
  c.Check(score_threshold > 0.0 && score_threshold <= 1.0, "score_threshold", score_threshold, "must be in (0, 1]");
  c.Check(person_score_threshold > 0.0 && person_score_threshold <= 1.0, "person_score_threshold",
          person_score_threshold, "must be in (0, 1]");
  c.InRange("threads", threads, 0, 64);
  c.InRange("timeout_ms", timeout_ms, 0, 60000);
  c.InRange("stride", stride, 1, 30);
  for (const auto& [name, w] : dynamic_weight) {
    const std::string key = "dynamic_weight." + name;
    c.Check(!name.empty(), key.c_str(), w, "needs a class name");
    c.InRange(key.c_str(), w, 1.0, 5.0);
  }
}

}  // namespace sgslam
