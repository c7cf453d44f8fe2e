#include "sgslam/common/sha256.h"

#include <openssl/evp.h>

#include <array>
#include <cctype>

#include "sgslam/common/error.h"
#include "sgslam/common/regular_file.h"

namespace sgslam {

std::string Sha256Hex(std::string_view bytes) {
  std::array<unsigned char, EVP_MAX_MD_SIZE> digest{};
  unsigned int length = 0;
  if (EVP_Digest(bytes.data(), bytes.size(), digest.data(), &length, EVP_sha256(), nullptr) != 1) {
    throw Error("OpenSSL could not compute a SHA-256 digest");
  }
  static constexpr char kHex[] = "0123456789abcdef";
  std::string hex;
  hex.reserve(2 * length);
  for (unsigned int i = 0; i < length; ++i) {
    hex += kHex[digest[i] >> 4];
    hex += kHex[digest[i] & 15];
  }
  return hex;
}

namespace {

// A SHA256SUMS list has a line of 66 bytes and a name per file: a folder of models
// lists a handful. These stop a wrong file early, and a name longer than any path.
constexpr std::uint64_t kMaxSumsBytes = 1 << 20;
constexpr std::size_t kMaxSumsLine = 66 + 4096;

}  // namespace

std::map<std::string, std::string> ReadSha256Sums(const std::filesystem::path& sums_file) {
  std::map<std::string, std::string> sums;
  const RegularFile file(sums_file, "checksum list");
  file.ForEachLine(kMaxSumsBytes, kMaxSumsLine, [&](int number, std::string_view line) {
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.empty() || line[0] == '#') return;
    // "<digest>  <name>" (text mode) or "<digest> *<name>" (binary mode).
    const bool ok = line.size() > 66 && line[64] == ' ' && (line[65] == ' ' || line[65] == '*');
    std::string digest = ok ? std::string(line.substr(0, 64)) : std::string();
    bool hex = ok;
    for (char& c : digest) {
      c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      hex = hex && std::isxdigit(static_cast<unsigned char>(c));
    }
    if (!hex) throw ParseError(sums_file.string(), number, "expected '<64 hex digits>  <file name>'");
    sums[std::filesystem::path(std::string(line.substr(66))).filename().string()] = digest;
  });
  return sums;
}

}  // namespace sgslam
