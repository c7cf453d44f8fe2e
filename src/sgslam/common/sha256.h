// SHA-256 of a byte string (OpenSSL), and checking files against a SHA256SUMS
// list in the format sha256sum writes ("<64 hex digits>  <file name>").
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>

namespace sgslam {

class RegularFile;

// Lower-case hex digest.
std::string Sha256Hex(std::string_view bytes);

// The digest of n bytes of file from offset, read in pieces: a file's checksum can
// be checked before the file is held in memory (a header that fits its size proves
// nothing of the gigabytes behind it). Throws InputError naming the file.
std::string Sha256HexOfFile(const RegularFile& file, std::uint64_t offset, std::uint64_t n);

// File name (without its folder) -> digest, as listed in a SHA256SUMS file (CRLF
// line ends too). Throws ParseError naming the file and line of a malformed entry,
// InputError naming it if it cannot be read, is not a regular file or is over 1 MiB.
std::map<std::string, std::string> ReadSha256Sums(const std::filesystem::path& sums_file);

}  // namespace sgslam
