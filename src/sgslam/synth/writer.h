// `sgslam synth`: saves a synthetic sequence in the TUM RGB-D layout, with exact
// ground truth beside it:
//   rgb/<t>.png depth/<t>.png mask/<t>.png   BGR8, 16-bit (m * 5000), 8-bit dynamic mask
//   rgb.txt depth.txt mask.txt associations.txt groundtruth.txt (T_w_c)
//   detections.txt (io/detections_file.h)  objects_gt.json  sgslam.yaml (camera)
//   movers.txt (each visible mover's pixels and visible centre per frame, world frame)
// Frames render on two worker threads; the files do not depend on the scheduling.
#pragma once

#include <atomic>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "sgslam/synth/depth_noise.h"

namespace sgslam::synth {

// frames, readout and depth_noise left unset take the preset's defaults
// (presets.h: 300 frames, a global shutter and exact depth; loop and repeat differ).
struct SynthOptions {
  std::string preset = "walkers";  // one of PresetNames()
  std::uint32_t seed = 1;          // scene layout, textures, paths and noise
  std::optional<int> frames;       // at 30 Hz
  bool force = false;              // write into a non-empty folder, replacing only what synth wrote there
  int threads = 2;                 // render workers
  std::optional<double> readout;   // s, rolling-shutter readout (synth/sequence.h); 0: global shutter
  std::optional<DepthNoise> depth_noise;
  // When set (a signal handler's flag), rendering stops: the frames rendered so far
  // (the first ones, in order) are kept and the list files written for them.
  const std::atomic<bool>* stop = nullptr;
};

struct SynthSummary {
  int frames = 0;
  std::string preset;
  std::uint32_t seed = 0;
  double readout = 0;  // s
  DepthNoise depth_noise = DepthNoise::kNone;
  double mean_dynamic_fraction = 0;  // mean share of mask pixels per frame
  std::filesystem::path out;
  double seconds = 0;  // wall time of rendering and writing
  bool stopped = false;  // options.stop ended it early: `frames` of the sequence's were written
};

// Throws InputError for a bad preset, frames <= 0, a bad readout, a non-empty folder
// without force or, with force, holding files of the layout that synth did not write
// (WrittenBySynth), or any file that cannot be written (naming it).
SynthSummary GenerateSequence(const SynthOptions& options, const std::filesystem::path& out);

// True when folder's sgslam.yaml is one sgslam synth wrote (it writes it first).
bool WrittenBySynth(const std::filesystem::path& folder);

// The camera section of sgslam.yaml, as written, with its readout (s).
std::string CameraYaml(double readout = 0);

}  // namespace sgslam::synth
