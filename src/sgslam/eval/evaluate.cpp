#include "sgslam/eval/evaluate.h"

#include <spdlog/spdlog.h>

#include <cstdio>

#include "sgslam/common/error.h"

namespace sgslam::eval {

Trajectory UniqueStamps(const Trajectory& sorted) {
  Trajectory out;
  out.reserve(sorted.size());
  for (const StampedPose& p : sorted) {
    if (!out.empty() && out.back().t == p.t) {
      out.back() = p;
    } else {
      out.push_back(p);
    }
  }
  return out;
}

EvalReport EvaluateFiles(const std::filesystem::path& gt, const std::filesystem::path& est,
                         const EvalOptions& options) {
  if (options.max_difference <= 0) throw ConfigError("max difference must be positive");
  if (options.rpe_delta <= 0) throw ConfigError("RPE delta must be positive");
  EvalReport r;
  r.gt_name = gt.string();
  r.est_name = est.string();
  r.options = options;
  r.gt = UniqueStamps(ReadTumTrajectory(gt));
  r.est = UniqueStamps(ReadTumTrajectory(est));
  spdlog::debug("eval: {} poses in {}, {} in {}", r.gt.size(), r.gt_name, r.est.size(), r.est_name);
  if (options.align_with.empty()) {
    r.ate = ComputeAte(r.gt, r.est, options.max_difference, r.gt_name, r.est_name);
  } else {
    const SE3 T_gt_est = ComputeAte(r.gt, UniqueStamps(ReadTumTrajectory(options.align_with)), options.max_difference,
                                    r.gt_name, options.align_with.string())
                             .T_gt_est;
    r.ate = ComputeAteAt(r.gt, r.est, T_gt_est, options.max_difference, r.gt_name, r.est_name);
  }
  try {
    r.rpe = ComputeRpe(r.gt, r.est, options.rpe_delta, r.gt_name, r.est_name);
  } catch (const InputError& e) {
    // A short estimate still has a meaningful ATE; report it instead of failing.
    r.rpe_note = e.what();
    spdlog::warn("RPE not computed: {}", r.rpe_note);
  }
  return r;
}

nlohmann::json ToJson(const ErrorStats& s) {
  return {{"rmse", s.rmse}, {"mean", s.mean}, {"median", s.median}, {"std", s.std},
          {"min", s.min},   {"max", s.max},   {"pairs", s.count}};
}

nlohmann::json ToJson(const EvalReport& r) {
  nlohmann::json j;
  j["gt"] = r.gt_name;
  j["est"] = r.est_name;
  j["ate"] = ToJson(r.ate.stats);
  j["ate"]["max_diff_s"] = ToSeconds(r.options.max_difference);
  if (!r.options.align_with.empty()) j["ate"]["aligned_with"] = r.options.align_with.string();
  const Eigen::Quaterniond& q = r.ate.T_gt_est.quaternion();
  const Eigen::Vector3d& t = r.ate.T_gt_est.translation();
  j["ate"]["T_gt_est"] = {{"t", {t.x(), t.y(), t.z()}}, {"q_xyzw", {q.x(), q.y(), q.z(), q.w()}}};
  if (r.rpe) {
    j["rpe"] = {{"delta_s", ToSeconds(r.rpe->delta)},
                {"pairs", r.rpe->pairs.size()},
                {"thinned", r.rpe->thinned},
                {"trans", ToJson(r.rpe->trans)},
                {"rot_deg", ToJson(r.rpe->rot_deg)}};
  } else {
    j["rpe"] = nullptr;
    j["rpe_note"] = r.rpe_note;
  }
  return j;
}

std::string FormatTable(const EvalReport& r) {
  std::string out;
  char buf[256];
  const auto line = [&](const char* fmt, auto... args) {
    std::snprintf(buf, sizeof buf, fmt, args...);
    out += buf;
  };
  out += "ground truth: " + r.gt_name + "\nestimate:     " + r.est_name + "\n";
  const ErrorStats& a = r.ate.stats;
  line("ATE [m] over %zu pairs (max difference %.3f s)\n", a.count, ToSeconds(r.options.max_difference));
  if (!r.options.align_with.empty()) out += "  aligned as " + r.options.align_with.string() + " (not refitted)\n";
  line("  rmse %.6f  mean %.6f  median %.6f  std %.6f  min %.6f  max %.6f\n", a.rmse, a.mean, a.median, a.std,
       a.min, a.max);
  if (!r.rpe) {
    out += "RPE: not computed: " + r.rpe_note + "\n";
    return out;
  }
  const ErrorStats &t = r.rpe->trans, &d = r.rpe->rot_deg;
  line("RPE over %.3f s, %zu pairs%s\n", ToSeconds(r.rpe->delta), r.rpe->pairs.size(),
       r.rpe->thinned ? " (evenly thinned)" : "");
  line("  %-10s %12s %12s\n", "", "trans [m]", "rot [deg]");
  line("  %-10s %12.6f %12.6f\n", "rmse", t.rmse, d.rmse);
  line("  %-10s %12.6f %12.6f\n", "mean", t.mean, d.mean);
  line("  %-10s %12.6f %12.6f\n", "median", t.median, d.median);
  line("  %-10s %12.6f %12.6f\n", "std", t.std, d.std);
  line("  %-10s %12.6f %12.6f\n", "min", t.min, d.min);
  line("  %-10s %12.6f %12.6f\n", "max", t.max, d.max);
  return out;
}

}  // namespace sgslam::eval
