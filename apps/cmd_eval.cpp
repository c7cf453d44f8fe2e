// `sgslam eval`: ATE and RPE of an estimated trajectory against ground truth, as
// TUM's evaluate_ate.py / evaluate_rpe.py define them (see src/sgslam/eval/).
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <memory>
#include <string>

#include "commands.h"
#include "sgslam/common/time.h"
#include "sgslam/eval/evaluate.h"
#include "sgslam/eval/plot.h"
#include "sgslam/io/atomic_write.h"
#include "sgslam/io/output_plan.h"

namespace sgslam::app {

namespace {

struct EvalArgs {
  std::string gt, est, plot, errors, align_with;
  double max_diff_s = 0.02;
  double delta_s = 1.0;
  bool json = false;
};

constexpr char kPngSignature[] = "\x89PNG\r\n\x1a\n";
constexpr char kErrorsHeader[] = "# timestamp ate_error_m\n";

// --plot and --errors neither over the trajectories read nor over each other, and
// over an existing file only when it is a plot (a PNG) or an errors file.
void CheckOutputs(const EvalArgs& a) {
  OutputPlan plan;
  plan.Reads(a.gt, "the trajectory given with --gt");
  plan.Reads(a.est, "the trajectory given with --est");
  plan.Reads(a.align_with, "the trajectory given with --align-with");
  if (!a.plot.empty()) plan.Writes(a.plot, "--plot", kPngSignature);
  if (!a.errors.empty()) plan.Writes(a.errors, "--errors", kErrorsHeader);
  plan.Check();
}

int RunEval(const EvalArgs& a) {
  CheckOutputs(a);
  spdlog::debug("eval: gt={} est={} max_diff={} s delta={} s plot={}", a.gt, a.est, a.max_diff_s, a.delta_s,
                a.plot.empty() ? "-" : a.plot);
  eval::EvalOptions options;
  options.max_difference = FromSeconds(a.max_diff_s);
  options.rpe_delta = FromSeconds(a.delta_s);
  options.align_with = a.align_with;
  const eval::EvalReport report = eval::EvaluateFiles(a.gt, a.est, options);
  // Plot before printing, so a failed plot leaves no half-reported result on stdout.
  if (!a.plot.empty()) {
    eval::WriteAtePlot(a.plot, report.gt, report.est, report.ate);
    spdlog::info("wrote {}", a.plot);
  }
  if (!a.errors.empty()) {
    // One line per associated pose: estimate time and its aligned position error,
    // to see where along a sequence the error grows.
    std::string text = kErrorsHeader;
    for (std::size_t k = 0; k < report.ate.pairs.size(); ++k) {
      text += FormatTimestamp(report.est[report.ate.pairs[k].second].t) + " " +
              std::to_string(report.ate.errors[k]) + "\n";
    }
    WriteFileAtomically(a.errors, text);
    spdlog::info("wrote {}", a.errors);
  }
  const std::string out = a.json ? eval::ToJson(report).dump() + "\n" : eval::FormatTable(report);
  std::fwrite(out.data(), 1, out.size(), stdout);
  std::fflush(stdout);
  return kExitOk;
}

}  // namespace

Action AddEvalCommand(CLI::App& root) {
  auto args = std::make_shared<EvalArgs>();
  CLI::App* sub = root.add_subcommand("eval", "ATE and RPE of an estimated trajectory (TUM benchmark definitions)");
  sub->add_option("--gt", args->gt, "Ground-truth trajectory, TUM format")->required();
  sub->add_option("--est", args->est, "Estimated trajectory, TUM format")->required();
  // Bounded so that the nanosecond conversion cannot overflow (1e10 s did, to a negative delta).
  sub->add_option("--max-diff", args->max_diff_s, "Max timestamp difference for association [s]")
      ->check(CLI::Range(1e-6, 1e6))
      ->capture_default_str();
  sub->add_option("--delta", args->delta_s, "RPE pose-pair spacing [s]")
      ->check(CLI::Range(1e-6, 1e6))
      ->capture_default_str();
  sub->add_option("--plot", args->plot, "Write a top-view ATE plot to this PNG file");
  sub->add_option("--errors", args->errors, "Write the per-pose ATE error (timestamp, metres) to this text file");
  sub->add_option("--align-with", args->align_with,
                  "Fit the ATE alignment on this trajectory instead (the run that made the map --est was localised in)")
      ->check(CLI::ExistingFile);
  sub->add_flag("--json", args->json, "Print one JSON object on stdout instead of a table");
  return [args]() -> int { return RunEval(*args); };
}

}  // namespace sgslam::app
