// The whole configuration: one plain struct per module, each in its module's
// folder with in-class defaults and the unit of each field in its comment. Each
// struct lists its fields once in Visit(), which the YAML loader, the printer, the
// unknown-key check and the reference (docs/configuration.md) all use, and checks
// its values in Validate(), which runs before any thread starts. Modules take their
// own section; only the system facade sees the whole.
#pragma once

#include <string>

#include "sgslam/camera/camera_config.h"
#include "sgslam/detection/detector_config.h"
#include "sgslam/dynamic/dynamic_config.h"
#include "sgslam/features/orb_config.h"
#include "sgslam/io/dataset_config.h"
#include "sgslam/loop/loop_config.h"
#include "sgslam/mapping/mapping_config.h"
#include "sgslam/semantic/semantic_config.h"
#include "sgslam/config/budget_config.h"
#include "sgslam/tracking/tracking_config.h"

namespace sgslam {

struct Config {
  CameraConfig camera;
  DatasetConfig dataset;
  OrbConfig orb;
  TrackingConfig tracking;
  MappingConfig mapping;
  DetectorConfig detector;
  DynamicConfig dynamic;
  SemanticConfig semantic;
  LoopConfig loop;
  BudgetConfig budget;

  template <class V>
  void VisitSections(V&& v) {
    v("camera", camera);
    v("dataset", dataset);
    v("orb", orb);
    v("tracking", tracking);
    v("mapping", mapping);
    v("detector", detector);
    v("dynamic", dynamic);
    v("semantic", semantic);
    v("loop", loop);
    v("budget", budget);
  }
  template <class V>
  void VisitSections(V&& v) const {
    const_cast<Config*>(this)->VisitSections(v);  // the visitors never write through const
  }

  // Throws ConfigError naming `source` and every bad key with its value.
  void Validate(const std::string& source) const;
};

}  // namespace sgslam
