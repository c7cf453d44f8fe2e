// Reading the line-based text files of the TUM layout (writing files: atomic_write.h).
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace sgslam {

// Calls fn(line_number, line) for every line of a text file, without its line end
// (CRLF too). The file must be a regular file (a FIFO or a device is refused, not
// waited on) of at most 1 GiB with lines of at most 64 KiB; a NUL byte in a line
// is refused. Every error names `what` and the path (and the line).
void ForEachTextLine(const std::filesystem::path& path, const std::string& what,
                     const std::function<void(int line, std::string_view text)>& fn);

// Calls fn(line_number, tokens) for every line that is not blank and does not start
// with '#'. Tokens are split on spaces, tabs and commas, as TUM's tools do.
// Throws InputError naming the path when the file is missing, not a regular file,
// too large or unreadable (ForEachTextLine).
void ForEachDataLine(const std::filesystem::path& path,
                     const std::function<void(int line, const std::vector<std::string_view>& tokens)>& fn);

// Parses a double; throws ParseError(path, line) naming the field when it is not one.
double ParseNumber(std::string_view token, const std::filesystem::path& path, int line, const char* what);

}  // namespace sgslam
