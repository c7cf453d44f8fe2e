// Place recognition and loop closing (ORB-SLAM2's settings unless a comment says otherwise).
#pragma once

#include <string>

#include "sgslam/common/config_checker.h"

namespace sgslam {

struct LoopConfig {
  // Place recognition (relocalisation from the whole map) and loop closing; off,
  // no vocabulary is loaded and a lost camera is sought near its last pose only.
  bool enabled = true;
  // Vocabulary file (`sgslam vocab train`); empty: the one shipped with sgslam.
  std::string vocabulary;

  template <class V>
  void Visit(V&& v) {
    v("enabled", enabled, "place recognition, relocalisation from the whole map and loop closing");
    v("vocabulary", vocabulary, "vocabulary file (sgslam vocab train); empty: the shipped one");
  }
  void Validate(ConfigChecker& c) const;
};

}  // namespace sgslam
