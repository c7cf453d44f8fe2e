#include "sgslam/semantic/object_json.h"

namespace sgslam {

nlohmann::json ObjectsJson(const std::vector<ObjectEstimate>& objects) {
  nlohmann::json list = nlohmann::json::array();
  for (const ObjectEstimate& o : objects) {
    if (!o.exported) continue;
    list.push_back({{"id", o.id},
                    {"class", o.class_name},
                    {"class_id", o.class_id},
                    {"confidence", o.confidence},
                    {"observations", o.observations},
                    {"complete", o.complete},
                    {"centroid", {o.centroid.x(), o.centroid.y(), o.centroid.z()}},
                    {"size", {o.size.x(), o.size.y(), o.size.z()}}});
  }
  return list;
}

}  // namespace sgslam
