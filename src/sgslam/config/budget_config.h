// The CPU budget (system/cpu_budget.h; a section of the whole system's, so here):
// how much of the machine sgslam may use, for robots that share their cores with
// their own work.
#pragma once

#include "sgslam/common/config_checker.h"

namespace sgslam {

struct BudgetConfig {
  // Cores the process may use at the camera's frame rate (1.0: one core); 0: no
  // budget. Over it, the detector's and the keyframe model's rates are lowered
  // first; tracking, local mapping and loop closing never.
  double cores = 0;

  template <class V>
  void Visit(V&& v) {
    v("cores", cores, "cores the system may use at the camera's rate; over it, detector and keyframe model run less; 0: no budget");
  }
  void Validate(ConfigChecker& c) const { c.InRange("cores", cores, 0.0, 256.0); }
};

}  // namespace sgslam
