// Collects every bad configuration value, then throws one ConfigError naming the
// source file, each key and each value (COLMAP-style CHECK_OPTION lines).
#pragma once

#include <cmath>
#include <sstream>
#include <type_traits>
#include <string>
#include <vector>

namespace sgslam {

class ConfigChecker {
 public:
  // section: the YAML section the following checks belong to ("camera").
  explicit ConfigChecker(std::string section) : section_(std::move(section)) {}

  template <class T>
  void Check(bool ok, const char* key, const T& value, const char* requirement) {
    if (ok) return;
    std::ostringstream s;
    s << section_ << "." << key << " = " << value << ": " << requirement;
    problems_.push_back(s.str());
  }
  template <class T>
  void Positive(const char* key, const T& value) {
    if constexpr (std::is_floating_point_v<T>) {
      if (!std::isfinite(value)) return Check(false, key, value, "must be a finite number > 0");
    }
    Check(value > T(0), key, value, "must be > 0");
  }
  template <class T>
  void InRange(const char* key, const T& value, const T& lo, const T& hi) {
    std::ostringstream r;
    r << "must be in [" << lo << ", " << hi << "]";
    const std::string req = r.str();
    Check(value >= lo && value <= hi, key, value, req.c_str());
  }

  void SetSection(std::string section) { section_ = std::move(section); }
  const std::vector<std::string>& problems() const { return problems_; }

 private:
  std::string section_;
  std::vector<std::string> problems_;
};

}  // namespace sgslam
