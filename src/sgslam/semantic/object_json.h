// The semantic objects as JSON, one form for objects.json and the viewer's page:
// id, class, class_id, confidence, observations, complete, centroid, size.
#pragma once

#include <vector>

#include <nlohmann/json.hpp>

#include "sgslam/semantic/objects.h"

namespace sgslam {

// The exported objects only (ObjectEstimate::exported), in their order.
nlohmann::json ObjectsJson(const std::vector<ObjectEstimate>& objects);

// The inverse, for a finished run's objects.json: objects marked exported. The
// list's class, confidence, centroid and size must have been checked (the viewer's
// ReadRunObjects does); id, class_id, observations and complete default when absent.
std::vector<ObjectEstimate> ObjectsFromJson(const nlohmann::json& list);

}  // namespace sgslam
