// sgslam synth: write a synthetic RGB-D sequence with exact ground truth (poses,
// depth, dynamic masks, detections, object boxes) in the TUM layout.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <memory>

#include "commands.h"
#include "sgslam/synth/writer.h"

namespace sgslam::app {

Action AddSynthCommand(CLI::App& root) {
  auto o = std::make_shared<synth::SynthOptions>();
  auto out = std::make_shared<std::string>();
  CLI::App* cmd = root.add_subcommand("synth", "Write a synthetic RGB-D sequence with exact ground truth");
  cmd->add_option("--out", *out, "Output folder (must be empty or new unless --force)")->required();
  cmd->add_option("--preset", o->preset, "Scene: static, walkers, degenerate, objects or rpy")->capture_default_str();
  cmd->add_option("--seed", o->seed, "Seed of the layout, textures, paths and noise")->capture_default_str();
  cmd->add_option("--frames", o->frames, "Number of frames at 30 Hz")->capture_default_str();
  cmd->add_option("--readout", o->readout,
                  "Rolling-shutter readout time in s (rows exposed one after another; 0: global shutter)")
      ->capture_default_str();
  cmd->add_flag("--force", o->force, "Write into a non-empty folder, replacing only the files synth writes");
  return [o, out] {
    const synth::SynthSummary s = synth::GenerateSequence(*o, *out);
    std::printf("synth: %d frames of preset '%s' (seed %u), mean dynamic fraction %.3f, written to %s in %.1f s\n",
                s.frames, s.preset.c_str(), s.seed, s.mean_dynamic_fraction, s.out.string().c_str(), s.seconds);
    return kExitOk;
  };
}

}  // namespace sgslam::app
