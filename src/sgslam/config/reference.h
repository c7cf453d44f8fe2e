// The configuration reference, generated from the config structs' own key lists
// (their Visit()) so that it cannot drift from the code: docs/configuration.md is
// `sgslam config --reference`, and a test keeps the two equal.
#pragma once

#include <string>

namespace sgslam {

// Whether a key is one most users set (configs/README.md); the others are advanced.
bool IsBasicKey(const std::string& section, const std::string& key);

// Markdown: per section, every key with its default, unit and meaning, and whether
// it is basic or advanced.
std::string ConfigReferenceMarkdown();

}  // namespace sgslam
