#include "sgslam/loop/loop_config.h"

namespace sgslam {

void LoopConfig::Validate(ConfigChecker&) const {}  // the vocabulary file is checked when it is loaded

}  // namespace sgslam
