// Typed errors for set-up and I/O problems. The message always names the file,
// key or value at fault; the library never calls exit(). The per-frame path
// returns states instead of throwing (see docs/architecture.md, "Conventions").
#pragma once

#include <stdexcept>
#include <string>

namespace sgslam {

// Base of every error the library throws on purpose.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Bad or missing input data: dataset folders, list files, images, trajectories.
class InputError : public Error {
 public:
  using Error::Error;
};

// A configuration value or key that cannot be used.
class ConfigError : public Error {
 public:
  using Error::Error;
};

// A file or stream line that cannot be parsed: "<file>:<line>: <what>".
class ParseError : public InputError {
 public:
  ParseError(const std::string& file, int line, const std::string& what)
      : InputError(file + ":" + std::to_string(line) + ": " + what) {}
};

}  // namespace sgslam
