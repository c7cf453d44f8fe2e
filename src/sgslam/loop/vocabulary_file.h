// Finding and loading the vocabulary place recognition uses (loop.vocabulary, or
// the one shipped with sgslam in share/sgslam/vocabulary/).
#pragma once

#include <filesystem>
#include <memory>
#include <string>

#include "sgslam/loop/keyframe_database.h"
#include "sgslam/loop/loop_config.h"

namespace sgslam {

// The shipped vocabulary, relative to the data folder (common/data_dir.h).
inline constexpr const char* kShippedVocabulary = "vocabulary/orb-k10-l5.vocab";

// configured, or the shipped vocabulary when empty. Throws InputError naming the
// file when it does not exist, with what to do instead.
std::filesystem::path ResolveVocabulary(const std::string& configured);

// An empty database over the configured vocabulary; null when loop.enabled is
// false. Throws InputError naming the file when it is missing or broken.
std::shared_ptr<KeyFrameDatabase> MakeKeyFrameDatabase(const LoopConfig& config);

}  // namespace sgslam
