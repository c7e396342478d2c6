// Output files are written whole or not at all: each goes to a temporary
// file in the same directory and is renamed into place.
#pragma once

#include <string>

namespace ipmc {

// Writes `content` to `path` atomically. Throws std::runtime_error naming
// the path on failure.
void WriteFileAtomically(const std::string& path, const std::string& content);

// Creates `dir` (and parents) if needed; throws naming the directory.
void EnsureDirectory(const std::string& dir);

}  // namespace ipmc
