// Whole-file reads with a size limit and atomic writes, with errors that name the file.
#pragma once

#include <cstddef>
#include <string>

namespace popcut {

inline constexpr std::size_t kMaxModelFileBytes = std::size_t{64} << 20;

// Reads a regular file (or "-" for standard input) of at most max_bytes; throws popcut::Error.
std::string read_text_file(const std::string& path, std::size_t max_bytes = kMaxModelFileBytes);

// Writes through a temporary file in the same directory and renames it over `path`, so a reader
// never sees half a file and a failed write leaves the old one intact. "-" writes to stdout.
void write_text_file(const std::string& path, const std::string& content);

}  // namespace popcut
