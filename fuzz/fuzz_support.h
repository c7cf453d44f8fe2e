// What the fuzz targets share: one scratch folder per process for the files the
// parsers read (they take paths), and the rule that tells a refusal from a finding.
// A parser may refuse an input only with the project's own errors (common/error.h);
// any other exception, a crash, a sanitizer report, or a result that breaks what
// the parser promises (FUZZ_CHECK) is a finding.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "sgslam/common/error.h"

namespace sgslam::fuzz {

inline std::string_view Bytes(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

// A folder made once per process (mkdtemp under $TMPDIR, else /dev/shm, else /tmp),
// removed at exit. Making it also turns the library's log off.
const std::filesystem::path& ScratchDir();

// Writes bytes to ScratchDir() / name, replacing what was there; returns the path.
std::filesystem::path WriteScratch(const std::string& name, std::string_view bytes);
// Removes ScratchDir() / name when it exists.
void RemoveScratch(const std::string& name);

// Whether the last input given to Parse was accepted (the corpus replay checks that
// every seed named valid-* still is).
bool LastInputAccepted();
void SetLastInputAccepted(bool accepted);
// The message of the last refusal ("" after an accepted input).
const std::string& LastRefusal();
void SetLastRefusal(std::string message);

// Prints the broken promise and aborts: a finding.
[[noreturn]] void Broken(const char* condition, const char* file, int line);

// Runs parse(); the project's errors are the expected refusals of bad input.
template <class F>
void Parse(F&& parse) {
  SetLastInputAccepted(false);
  SetLastRefusal("");
  try {
    parse();
    SetLastInputAccepted(true);
  } catch (const sgslam::Error& e) {
    SetLastRefusal(e.what());
  }
}

}  // namespace sgslam::fuzz

// What a parser promises of what it returns.
#define FUZZ_CHECK(condition) \
  ((condition) ? static_cast<void>(0) : ::sgslam::fuzz::Broken(#condition, __FILE__, __LINE__))
