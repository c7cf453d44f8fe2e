#include "sgslam/config/config.h"

#include "sgslam/common/error.h"

namespace sgslam {

void Config::Validate(const std::string& source) const {
  ConfigChecker checker("");
  VisitSections([&](const char* name, const auto& section) {
    checker.SetSection(name);
    section.Validate(checker);
  });
  if (checker.problems().empty()) return;
  std::string message = "invalid configuration (" + source + "):";
  for (const auto& p : checker.problems()) message += "\n  " + p;
  throw ConfigError(message);
}

}  // namespace sgslam
