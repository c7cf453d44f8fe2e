#include "sgslam/loop/vocabulary_file.h"

#include "sgslam/common/data_dir.h"
#include "sgslam/common/error.h"
#include "sgslam/common/regular_file.h"

namespace sgslam {

namespace fs = std::filesystem;

fs::path ResolveVocabulary(const std::string& configured) {
  static const std::string kInstead = "; set loop.vocabulary to a file `sgslam vocab train` wrote, or run without "
                                      "place recognition with loop.enabled: false";
  if (!configured.empty()) {
    if (const std::string why = WhyNotRegularFile(configured); why == kNotFound) {
      throw InputError("loop.vocabulary: no such file " + configured + kInstead);
    } else if (!why.empty()) {
      throw InputError("loop.vocabulary: " + configured + " " + why + kInstead);
    }
    return configured;
  }
  const auto data = DataDir();
  if (!data) throw InputError("the vocabulary shipped with sgslam was not found (no share/sgslam beside the executable)" + kInstead);
  const fs::path file = *data / kShippedVocabulary;
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) throw InputError("the vocabulary shipped with sgslam is missing: " + file.string() + kInstead);
  return file;
}

std::shared_ptr<KeyFrameDatabase> MakeKeyFrameDatabase(const LoopConfig& config) {
  if (!config.enabled) return nullptr;
  auto vocabulary = std::make_shared<const vocab::Vocabulary>(vocab::Vocabulary::Load(ResolveVocabulary(config.vocabulary)));
  return std::make_shared<KeyFrameDatabase>(std::move(vocabulary));
}

}  // namespace sgslam
