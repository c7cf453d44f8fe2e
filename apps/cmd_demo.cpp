// sgslam demo: the whole job on an embedded default. Generates a short synthetic
// sequence with people walking through the view, runs the system on it and
// evaluates the trajectory against the exact ground truth.
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <memory>

#include "commands.h"
#include "run_pipeline.h"
#include "stop_signals.h"
#include "sgslam/io/output_plan.h"
#include "sgslam/synth/writer.h"

namespace sgslam::app {

namespace {

struct DemoOptions {
  std::string out = "sgslam-out/demo";
  int frames = 150;
};

int RunDemo(const DemoOptions& o) {
  const std::filesystem::path out = o.out;
  OutputPlan plan;
  plan.WritesFolder(out, "--out");
  plan.Check();
  synth::SynthOptions so;
  so.preset = "walkers";
  so.frames = o.frames;
  so.force = true;  // the demo's own sequence, regenerated on every run (a folder synth did not write is refused)
  std::printf("1/3 generating a synthetic 'walkers' sequence (%d frames, people walking through the view)...\n",
              o.frames);
  synth::SynthSummary synth;
  {
    const StopSignals signals;  // Ctrl-C: the frames so far are listed, and the demo ends
    so.stop = &StopSignals::Flag();
    synth = synth::GenerateSequence(so, out / "sequence");
  }
  if (synth.stopped) {
    std::printf("demo: stopped by %s while generating the sequence\n", SignalName(StopSignals::Received()));
    return 128 + StopSignals::Received();
  }
  std::printf("    %s: %.0f %% of the image moves on average (%.1f s)\n", synth.out.string().c_str(),
              100 * synth.mean_dynamic_fraction, synth.seconds);

  // SG-SLAM (Algorithm 1 with the sequence's ground-truth boxes standing in for the
  // detector) against the same system with rejection off, as in the paper's Table VI,
  // and against plain tracking, where every map point may set the pose at once
  // (ORB-SLAM2; tracking.refinements.trusted_points false): the two defences one by one.
  struct Variant {
    const char* name;
    const char* mode;
    const char* what;
    bool plain;
  };
  const Variant variants[3] = {
      {"sg", "sg", "dynamic features rejected (Algorithm 1), trusted map points", false},
      {"none", "none", "no rejection, trusted map points", false},
      {"plain", "none", "no rejection, every map point sets the pose (ORB-SLAM2)", true},
  };
  std::printf("2/3 running SLAM on it three times:\n");
  RunSummary runs[3];
  for (int k = 0; k < 3; ++k) {
    RunOptions ro;
    ro.dataset = (out / "sequence").string();
    ro.out = (out / (std::string("run-") + variants[k].name)).string();
    ro.mode = variants[k].mode;
    ro.print_objects = false;  // the walkers scene has no detector classes
    if (variants[k].plain) {
      ro.tweak = [](Config& c) { c.tracking.refinements.trusted_points = false; };
      ro.tweak_name = "tracking.refinements.trusted_points false";
    }
    runs[k] = RunSequence(ro);
    std::printf("    %-5s (%s)\n          %s\n", variants[k].name, variants[k].what, FormatSummary(runs[k]).c_str());
  }

  std::printf("3/3 evaluation against the ground truth (ATE RMSE after rigid alignment):\n");
  for (int k = 0; k < 3; ++k) {
    if (runs[k].ate_rmse) {
      std::printf("    %-5s  %.4f m  (%zu of %zu frames tracked)\n", variants[k].name, *runs[k].ate_rmse, runs[k].tracked,
                  runs[k].frames);
    } else {
      std::printf("    %-5s  no ATE: too few tracked frames\n", variants[k].name);
    }
  }
  std::printf(
      "Plot it: sgslam eval --gt %s --est %s --plot %s\n",
      (out / "sequence" / "groundtruth.txt").string().c_str(), (out / "run-sg" / "trajectory.txt").string().c_str(),
      (out / "run-sg" / "ate.png").string().c_str());
  return kExitOk;
}

}  // namespace

Action AddDemoCommand(CLI::App& root) {
  auto o = std::make_shared<DemoOptions>();
  CLI::App* cmd = root.add_subcommand("demo", "Generate a dynamic synthetic sequence, run SLAM on it and evaluate");
  cmd->add_option("--out", o->out, "Output folder (default: ./sgslam-out/demo)");
  cmd->add_option("--frames", o->frames, "Frames to generate")->check(CLI::Range(30, 3000));
  return [o] { return RunDemo(*o); };
}

}  // namespace sgslam::app
