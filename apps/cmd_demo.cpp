// sgslam demo: the whole job on an embedded default. Generates a short synthetic
// sequence with people walking through the view; running and evaluating SLAM on
// it follows once tracking exists.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <memory>

#include "commands.h"
#include "sgslam/synth/writer.h"

namespace sgslam::app {

namespace {

struct DemoOptions {
  std::string out = "sgslam-out/demo";
  int frames = 150;
};

int RunDemo(const DemoOptions& o) {
  const std::filesystem::path out = o.out;
  synth::SynthOptions so;
  so.preset = "walkers";
  so.frames = o.frames;
  so.force = true;  // the demo's own folder: regenerated on every run
  std::printf("generating a synthetic 'walkers' sequence (%d frames, people walking through the view)...\n", o.frames);
  const synth::SynthSummary s = synth::GenerateSequence(so, out / "sequence");
  std::printf("%s: %.0f %% of the image moves on average (%.1f s)\n", s.out.string().c_str(),
              100 * s.mean_dynamic_fraction, s.seconds);
  std::printf("Tracking is not implemented yet, so the demo stops here: no trajectory and no ATE.\n");
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
