// sgslam synth: write a synthetic RGB-D sequence with exact ground truth (poses,
// depth, dynamic masks, detections, object boxes) in the TUM layout.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <memory>

#include "commands.h"
#include "stop_signals.h"
#include "sgslam/io/output_plan.h"
#include "sgslam/synth/presets.h"
#include "sgslam/synth/writer.h"

namespace sgslam::app {

Action AddSynthCommand(CLI::App& root) {
  auto o = std::make_shared<synth::SynthOptions>();
  auto out = std::make_shared<std::string>();
  CLI::App* cmd = root.add_subcommand("synth", "Write a synthetic RGB-D sequence with exact ground truth");
  cmd->add_option("--out", *out, "Output folder (must be empty or new unless --force)")->required();
  std::string presets;
  for (const std::string& name : synth::PresetNames()) presets += (presets.empty() ? "" : ", ") + name;
  cmd->add_option("--preset", o->preset, "Scene: " + presets)->capture_default_str();
  cmd->add_option("--seed", o->seed, "Seed of the layout, textures, paths and noise")->capture_default_str();
  // Unset, these three take the preset's defaults (synth/presets.h).
  cmd->add_option_function<int>(
      "--frames", [o](const int& n) { o->frames = n; },
      "Number of frames at 30 Hz (default 300; loop 1801: two laps; repeat 601)");
  cmd->add_option_function<double>(
      "--readout", [o](const double& s) { o->readout = s; },
      "Rolling-shutter readout time in s (rows exposed one after another; 0: global shutter; default 0, "
      "loop and repeat 0.03)");
  cmd->add_option_function<std::string>(
         "--depth-noise", [o](const std::string& n) { o->depth_noise = synth::ParseDepthNoise(n); },
         "Depth sensor: none (exact) or kinect (noise, quantisation, shadows; default none, loop and repeat kinect)")
      ->check(CLI::IsMember({"none", "kinect"}));
  cmd->add_flag("--force", o->force, "Write into a non-empty folder, replacing only the files synth writes");
  return [o, out] {
    OutputPlan plan;
    plan.WritesFolder(*out, "--out");
    plan.Check();
    // Stopped part-way, the frames rendered so far are kept and listed (a usable,
    // shorter sequence) instead of a folder without its lists.
    const StopSignals signals;
    o->stop = &StopSignals::Flag();
    const synth::SynthSummary s = synth::GenerateSequence(*o, *out);
    if (s.stopped) {
      std::printf("synth: stopped by %s: the first %d frames are written and listed in %s\n",
                  SignalName(StopSignals::Received()), s.frames, s.out.string().c_str());
      return 128 + StopSignals::Received();
    }
    std::printf("synth: %d frames of preset '%s' (seed %u, readout %g s, depth noise %s), mean dynamic fraction %.3f, "
                "written to %s in %.1f s\n",
                s.frames, s.preset.c_str(), s.seed, s.readout, synth::DepthNoiseName(s.depth_noise),
                s.mean_dynamic_fraction, s.out.string().c_str(), s.seconds);
    return kExitOk;
  };
}

}  // namespace sgslam::app
