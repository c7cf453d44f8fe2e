#include "sgslam/semantic/object_json.h"

#include <cmath>

namespace sgslam {

namespace {

nlohmann::json ObjectJson(const ObjectEstimate& o) {
  return {{"id", o.id},
          {"class", o.class_name},
          {"class_id", o.class_id},
          {"class_share", o.class_share},
          {"confidence", o.confidence},
          {"confirmed", o.confirmed},
          {"plausible", o.plausible},
          {"observations", o.observations},
          {"views_expected", o.views_expected},
          {"views_seen", o.views_seen},
          {"spread_deg", o.spread_deg},
          {"points", o.points},
          {"complete", o.complete},
          {"centroid", {o.centroid.x(), o.centroid.y(), o.centroid.z()}},
          {"size", {o.size.x(), o.size.y(), o.size.z()}},
          {"dimensions", {o.dimensions.x(), o.dimensions.y(), o.dimensions.z()}}};
}

}  // namespace

nlohmann::json ObjectsJson(const std::vector<ObjectEstimate>& objects, bool candidates) {
  nlohmann::json list = nlohmann::json::array();
  for (const ObjectEstimate& o : objects) {
    if (o.exported != candidates) list.push_back(ObjectJson(o));
  }
  return list;
}

std::string ObjectLabel(const ObjectEstimate& o) {
  return o.class_name + " " + std::to_string(static_cast<int>(std::lround(100 * o.class_share))) + "% \u00b7 " +
         std::to_string(o.observations) + " views";
}

std::vector<ObjectEstimate> ObjectsFromJson(const nlohmann::json& list) {
  std::vector<ObjectEstimate> objects;
  for (const nlohmann::json& o : list) {
    ObjectEstimate e;
    e.id = o.value("id", static_cast<int>(objects.size() + 1));
    e.class_id = o.value("class_id", -1);
    e.class_name = o.at("class").get<std::string>();
    e.confidence = o.at("confidence").get<double>();
    e.class_share = o.value("class_share", 1.0);
    e.confirmed = o.value("confirmed", true);
    e.plausible = o.value("plausible", true);
    e.observations = o.value("observations", 0);
    e.views_expected = o.value("views_expected", 0);
    e.views_seen = o.value("views_seen", 0);
    e.spread_deg = o.value("spread_deg", 0.0);
    e.points = o.value("points", 0);
    e.complete = o.value("complete", true);
    for (int k = 0; k < 3; ++k) {
      e.centroid[k] = o.at("centroid").at(k).get<double>();
      e.size[k] = o.at("size").at(k).get<double>();
      if (o.contains("dimensions")) e.dimensions[k] = o.at("dimensions").at(k).get<double>();
    }
    e.exported = e.confirmed && e.plausible;
    objects.push_back(std::move(e));
  }
  return objects;
}

}  // namespace sgslam
