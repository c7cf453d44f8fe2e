// Reading the line-based text files of the TUM layout, and saving files so that a
// crash or a full disk never leaves a half-written result behind.
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

// Writes to a new uniquely named file beside path (created exclusively, so a
// planted link is never followed) and renames it over path, so readers see the old
// or the new file, never a torn one; the temporary file is removed on failure. Throws InputError naming the path on failure.
// The temporary files of path that a killed writer left are removed first
// (RemoveStaleTempFiles).
void WriteFileAtomically(const std::filesystem::path& path, const std::string& content);

// Removes the files "<path>.tmp.<pid>.<suffix>" (the temporary names of the writers
// of path) whose writer is gone: no process <pid>, or one started after the file
// was last written (the id reused). Only SIGKILL or a power cut leaves them.
void RemoveStaleTempFiles(const std::filesystem::path& path);

}  // namespace sgslam
