// The configuration reference, generated from the config structs' own key lists
// (their Visit()) so that it cannot drift from the code: docs/configuration.md is
// `sgslam config --reference`, and a test keeps the two equal.
#pragma once

#include <string>

namespace sgslam {

// Markdown: per section, every key with its default, unit and meaning (sub-sections'
// switches as `sub.key`), then the keys earlier versions had (removed_keys.h).
std::string ConfigReferenceMarkdown();

}  // namespace sgslam
