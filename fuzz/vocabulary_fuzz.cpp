// Vocabulary files (vocab/vocabulary.h), then the descent of a few descriptors
// through the tree that loaded. The file ends in the SHA-256 of what comes before
// it, which a mutation almost never keeps right: each input is read as it is (the
// size, header and checksum checks), then with its node count and checksum made to
// agree with its length (the tree's own checks), the reading that counts as the
// input's outcome.
#include <cmath>
#include <cstring>

#include "fuzz_support.h"
#include "sgslam/common/sha256.h"
#include "sgslam/vocab/vocabulary.h"

namespace {

constexpr std::size_t kHeaderBytes = 8 + 4 * 4 + 8;
constexpr std::size_t kCountAt = 8 + 4 * 3;
constexpr std::size_t kNodeBytes = 2 + sgslam::vocab::kDescriptorBytes + 4;
constexpr std::size_t kChecksumChars = 64;

// The input with the node count its length implies and the checksum of its body.
std::string Consistent(std::string_view in) {
  if (in.size() < kHeaderBytes + kChecksumChars) return std::string(in);
  const std::uint32_t count = static_cast<std::uint32_t>((in.size() - kHeaderBytes - kChecksumChars) / kNodeBytes);
  std::string body(in.substr(0, kHeaderBytes + count * kNodeBytes));
  std::memcpy(body.data() + kCountAt, &count, sizeof count);
  return body + sgslam::Sha256Hex(body);
}

void Load(const std::filesystem::path& path) {
  using sgslam::vocab::Vocabulary;
  const Vocabulary v = Vocabulary::Load(path);
  FUZZ_CHECK(v.size() > 0 && v.nodes() > v.size() && v.Serialize().size() == std::filesystem::file_size(path));
  cv::Mat descriptors(8, sgslam::vocab::kDescriptorBytes, CV_8U);
  for (int i = 0; i < descriptors.rows; ++i) {
    for (int j = 0; j < descriptors.cols; ++j) descriptors.at<std::uint8_t>(i, j) = static_cast<std::uint8_t>(i * 37 + j * j);
  }
  for (int up = 0; up <= v.levels(); ++up) {
    const sgslam::vocab::BowData bow = v.Transform(descriptors, up);
    double sum = 0;
    for (const auto& [word, weight] : bow.words) {
      FUZZ_CHECK(word < v.size() && std::isfinite(weight));
      sum += weight;
    }
    FUZZ_CHECK(bow.words.empty() || std::abs(sum - 1) < 1e-3);
    for (const auto& [node, keypoints] : bow.nodes) FUZZ_CHECK(node < v.nodes() && !keypoints.empty());
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace sgslam;
  const std::string_view in = fuzz::Bytes(data, size);
  fuzz::Parse([&] { Load(fuzz::WriteScratch("raw.vocab", in)); });
  fuzz::Parse([&] { Load(fuzz::WriteScratch("consistent.vocab", Consistent(in))); });
  return 0;
}
