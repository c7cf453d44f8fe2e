// The semantic objects as JSON, one form for objects.json and the viewer's page:
// id, class, class_id, class_share, confidence, confirmed, plausible, observations,
// views_expected, views_seen, spread_deg, points, complete, centroid, size,
// dimensions (docs/object-map.md says what each means).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sgslam/semantic/objects.h"

namespace sgslam {

// The exported objects (ObjectEstimate::exported), in their order; candidates true:
// the others (unconfirmed, or of a size their class cannot have).
nlohmann::json ObjectsJson(const std::vector<ObjectEstimate>& objects, bool candidates = false);

// The inverse, for a finished run's objects.json. The list's class, confidence,
// centroid and size must have been checked (the viewer's ReadRunObjects does); the
// other fields default when absent (an earlier objects.json: confirmed, plausible).
std::vector<ObjectEstimate> ObjectsFromJson(const nlohmann::json& list);

// An object's label where it is drawn (the viewer's page, Rviz, Foxglove): its
// class, the class's share of the views' votes and the views, "tvmonitor 75% · 8 views".
std::string ObjectLabel(const ObjectEstimate& o);

}  // namespace sgslam
