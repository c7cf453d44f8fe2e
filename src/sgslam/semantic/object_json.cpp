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

std::vector<ObjectEstimate> ObjectsFromJson(const nlohmann::json& list) {
  std::vector<ObjectEstimate> objects;
  for (const nlohmann::json& o : list) {
    ObjectEstimate e;
    e.id = o.value("id", static_cast<int>(objects.size() + 1));
    e.class_id = o.value("class_id", -1);
    e.class_name = o.at("class").get<std::string>();
    e.confidence = o.at("confidence").get<double>();
    e.observations = o.value("observations", 0);
    e.complete = o.value("complete", true);
    for (int k = 0; k < 3; ++k) {
      e.centroid[k] = o.at("centroid").at(k).get<double>();
      e.size[k] = o.at("size").at(k).get<double>();
    }
    e.exported = true;
    objects.push_back(std::move(e));
  }
  return objects;
}

}  // namespace sgslam
