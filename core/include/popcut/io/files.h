// Whole-file reads with a size limit and atomic writes, with errors that name the file.
#pragma once

#include <cstddef>
#include <functional>
#include <iosfwd>
#include <string>

namespace popcut {

// Every model within the cell limit fits in far less; the JSON parser holds the whole document.
inline constexpr std::size_t kMaxModelFileBytes = std::size_t{32} << 20;

// Reads a regular file (or "-" for standard input) of at most max_bytes; throws popcut::Error.
std::string read_text_file(const std::string& path, std::size_t max_bytes = kMaxModelFileBytes);

// Writes through a temporary file in the same directory and renames it over `path`, so a reader
// never sees half a file and a failed write leaves the old one intact. "-" writes to stdout.
void write_text_file(const std::string& path, const std::string& content);

// The same guarantees, with the content streamed by `write` instead of held in memory.
void write_text_file(const std::string& path, const std::function<void(std::ostream&)>& write);

}  // namespace popcut
