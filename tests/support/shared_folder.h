// Folders made once and shared by the tests of one test program. CTest runs each
// test in a process of its own, so a suite whose tests all render the same synthetic
// sequence used to render it once per test.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

#include "sgslam/synth/writer.h"

namespace sgslam::test {

// The folder <build>/tests/shared/<program>/<name>.<stamp>, made by make(folder)
// (given an empty folder) on first use and kept while the test program is not
// rebuilt: <stamp> is the program file's (size, time). Safe with several processes
// asking at once (ctest -j, two ctest runs): the first makes it under a lock while
// the others wait, each holds a shared lock on the folder until it exits, and a
// folder of another build is removed, when a new one is made, only if no process
// holds it. The tests must only read it. make throws on failure; nothing is kept.
std::filesystem::path SharedFolder(const std::string& name,
                                   const std::function<void(const std::filesystem::path&)>& make);

// synth::GenerateSequence(o) in a SharedFolder named after o (preset, frames, seed,
// readout, depth noise).
std::filesystem::path SharedSequence(const synth::SynthOptions& o);

}  // namespace sgslam::test
