#include "sgslam/eval/object_score.h"

#include <algorithm>
#include <limits>

#include "sgslam/common/error.h"
#include "sgslam/common/regular_file.h"
#include "sgslam/common/stats.h"

namespace sgslam::eval {

namespace {

// The gate (see the header): the true box grown by this, or this far from its centre.
constexpr double kGateMargin = 0.15;   // m
constexpr double kGateDistance = 0.30;  // m
// A match of another class counts as this much further away: two objects side by
// side go to the estimate of their own class.
constexpr double kClassPenalty = 0.20;  // m
constexpr std::uint64_t kMaxTruthBytes = 4 << 20;

Eigen::Vector3d Vector3(const nlohmann::json& j, const char* key, const std::string& what) {
  if (!j.contains(key) || !j.at(key).is_array() || j.at(key).size() != 3) {
    throw InputError(what + ": \"" + key + "\" must be an array of 3 numbers");
  }
  Eigen::Vector3d v;
  for (int k = 0; k < 3; ++k) {
    if (!j.at(key).at(k).is_number()) throw InputError(what + ": \"" + key + "\" must be an array of 3 numbers");
    v[k] = j.at(key).at(k).get<double>();
    if (!std::isfinite(v[k])) throw InputError(what + ": \"" + key + "\" is not finite");
  }
  return v;
}

bool InGate(const Eigen::Vector3d& p, const TrueObject& t) {
  const Eigen::Vector3d half = t.size / 2 + Eigen::Vector3d::Constant(kGateMargin);
  return ((p - t.centroid).cwiseAbs().array() <= half.array()).all() || (p - t.centroid).norm() <= kGateDistance;
}

}  // namespace

std::vector<TrueObject> LoadObjectTruth(const std::filesystem::path& path) {
  const std::string name = path.string();
  const nlohmann::json doc = nlohmann::json::parse(ReadRegularFile(path, "object truth", kMaxTruthBytes), nullptr, false);
  if (doc.is_discarded() || !doc.is_object() || !doc.contains("objects") || !doc.at("objects").is_array()) {
    throw InputError(name + ": not a list of true objects (a JSON object with an \"objects\" array)");
  }
  std::vector<TrueObject> out;
  int index = 0;
  for (const nlohmann::json& o : doc.at("objects")) {
    const std::string what = name + ": object " + std::to_string(++index);
    if (!o.is_object() || !o.contains("class") || !o.at("class").is_string()) {
      throw InputError(what + ": needs a \"class\" string");
    }
    const auto flag = [&](const char* key, bool fallback) {
      if (!o.contains(key)) return fallback;
      if (!o.at(key).is_boolean()) throw InputError(what + ": \"" + key + "\" must be true or false");
      return o.at(key).get<bool>();
    };
    const bool moves = flag("dynamic", false) || !flag("static", true);
    // A mover has no one place (sgslam synth gives none): nothing to match.
    if (moves && !o.contains("centroid")) continue;
    TrueObject t;
    t.id = o.contains("id") && o.at("id").is_number_integer() ? o.at("id").get<int>() : index;
    t.class_name = o.at("class").get<std::string>();
    t.centroid = Vector3(o, "centroid", what);
    t.size = Vector3(o, "size", what);
    if ((t.size.array() < 0).any()) throw InputError(what + ": \"size\" must not be negative");
    t.scored = !moves && flag("coco", true);
    out.push_back(std::move(t));
  }
  return out;
}

ObjectScore ScoreObjects(const std::vector<TrueObject>& truth, const std::vector<ObjectEstimate>& estimates) {
  ObjectScore s;
  s.estimates = static_cast<int>(estimates.size());
  for (const TrueObject& t : truth) s.truths += t.scored ? 1 : 0;
  s.matches.resize(estimates.size());
  for (std::size_t e = 0; e < estimates.size(); ++e) {
    s.matches[e].estimate_id = estimates[e].id;
    s.matches[e].estimate_class = estimates[e].class_name;
    s.matches[e].centroid = estimates[e].centroid;
    s.matches[e].size = estimates[e].size;
  }
  // Every admissible pair, nearest (class-penalised) first, one to one.
  struct Pair {
    double cost;
    std::size_t e, t;
  };
  std::vector<Pair> pairs;
  for (std::size_t e = 0; e < estimates.size(); ++e) {
    for (std::size_t t = 0; t < truth.size(); ++t) {
      if (!InGate(estimates[e].centroid, truth[t])) continue;
      const double d = (estimates[e].centroid - truth[t].centroid).norm();
      pairs.push_back({d + (estimates[e].class_name == truth[t].class_name ? 0.0 : kClassPenalty), e, t});
    }
  }
  std::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) { return a.cost < b.cost; });
  std::vector<bool> e_done(estimates.size(), false), t_done(truth.size(), false);
  std::vector<double> centroid_errors, size_errors;
  for (const Pair& p : pairs) {
    if (e_done[p.e] || t_done[p.t]) continue;
    e_done[p.e] = t_done[p.t] = true;
    ObjectMatch& m = s.matches[p.e];
    const TrueObject& t = truth[p.t];
    m.truth_id = t.id;
    m.centroid_error = (m.centroid - t.centroid).norm();
    m.size_error = (m.size - t.size).norm() / std::max(t.size.norm(), 1e-6);
    if (!t.scored) {
      m.kind = ObjectMatch::kUnscored;
      ++s.unscored;
      continue;
    }
    m.kind = ObjectMatch::kMatched;
    ++s.matched;
    s.correct_class += m.estimate_class == t.class_name ? 1 : 0;
    centroid_errors.push_back(m.centroid_error);
    size_errors.push_back(m.size_error);
  }
  // The rest: a duplicate of the nearest true object whose gate holds it, else false.
  for (std::size_t e = 0; e < estimates.size(); ++e) {
    if (e_done[e]) continue;
    ObjectMatch& m = s.matches[e];
    double best = std::numeric_limits<double>::infinity();
    for (const TrueObject& t : truth) {
      const double d = (m.centroid - t.centroid).norm();
      if (InGate(m.centroid, t) && d < best) {
        best = d;
        m.truth_id = t.id;
        m.centroid_error = d;
        m.kind = t.scored ? ObjectMatch::kDuplicate : ObjectMatch::kUnscored;
      }
    }
    if (m.kind == ObjectMatch::kDuplicate) ++s.duplicates;
    if (m.kind == ObjectMatch::kUnscored) ++s.unscored;
    if (m.kind == ObjectMatch::kFalse) ++s.false_positives;
  }
  for (std::size_t t = 0; t < truth.size(); ++t) {
    if (truth[t].scored && !t_done[t]) s.missed.push_back(truth[t].id);
  }
  const int judged = s.matched + s.duplicates + s.false_positives;
  s.precision = judged > 0 ? static_cast<double>(s.matched) / judged : 0.0;
  s.recall = s.truths > 0 ? static_cast<double>(s.matched) / s.truths : 0.0;
  s.class_accuracy = s.matched > 0 ? static_cast<double>(s.correct_class) / s.matched : 0.0;
  s.median_centroid_error = Median(centroid_errors);
  s.median_size_error = Median(size_errors);
  return s;
}

nlohmann::json ToJson(const ObjectScore& s) {
  static const char* kKinds[] = {"matched", "duplicate", "false", "unscored"};
  nlohmann::json matches = nlohmann::json::array();
  for (const ObjectMatch& m : s.matches) {
    matches.push_back({{"id", m.estimate_id},
                       {"class", m.estimate_class},
                       {"centroid", {m.centroid.x(), m.centroid.y(), m.centroid.z()}},
                       {"size", {m.size.x(), m.size.y(), m.size.z()}},
                       {"truth", m.truth_id},
                       {"kind", kKinds[m.kind]},
                       {"centroid_error", m.centroid_error},
                       {"size_error", m.size_error}});
  }
  return {{"estimates", s.estimates},
          {"truths", s.truths},
          {"matched", s.matched},
          {"duplicates", s.duplicates},
          {"false_positives", s.false_positives},
          {"unscored", s.unscored},
          {"precision", s.precision},
          {"recall", s.recall},
          {"class_accuracy", s.class_accuracy},
          {"median_centroid_error", s.median_centroid_error},
          {"median_size_error", s.median_size_error},
          {"missed", s.missed},
          {"objects", matches}};
}

}  // namespace sgslam::eval
