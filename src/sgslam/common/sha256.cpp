#include "sgslam/common/sha256.h"

#include <openssl/evp.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <memory>

#include "sgslam/common/error.h"
#include "sgslam/common/regular_file.h"

namespace sgslam {

namespace {

std::string Hex(const unsigned char* digest, unsigned int length) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string hex;
  hex.reserve(2 * length);
  for (unsigned int i = 0; i < length; ++i) {
    hex += kHex[digest[i] >> 4];
    hex += kHex[digest[i] & 15];
  }
  return hex;
}

[[noreturn]] void Unavailable() { throw Error("OpenSSL could not compute a SHA-256 digest"); }

}  // namespace

std::string Sha256Hex(std::string_view bytes) {
  std::array<unsigned char, EVP_MAX_MD_SIZE> digest{};
  unsigned int length = 0;
  if (EVP_Digest(bytes.data(), bytes.size(), digest.data(), &length, EVP_sha256(), nullptr) != 1) Unavailable();
  return Hex(digest.data(), length);
}

std::string Sha256HexOfFile(const RegularFile& file, std::uint64_t offset, std::uint64_t n) {
  const std::unique_ptr<EVP_MD_CTX, void (*)(EVP_MD_CTX*)> context(EVP_MD_CTX_new(), EVP_MD_CTX_free);
  if (!context || EVP_DigestInit_ex(context.get(), EVP_sha256(), nullptr) != 1) Unavailable();
  std::string piece;
  for (std::uint64_t done = 0; done < n;) {
    piece.resize(static_cast<std::size_t>(std::min<std::uint64_t>(n - done, 1 << 20)));
    file.ReadInto(offset + done, piece);
    if (EVP_DigestUpdate(context.get(), piece.data(), piece.size()) != 1) Unavailable();
    done += piece.size();
  }
  std::array<unsigned char, EVP_MAX_MD_SIZE> digest{};
  unsigned int length = 0;
  if (EVP_DigestFinal_ex(context.get(), digest.data(), &length) != 1) Unavailable();
  return Hex(digest.data(), length);
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
