// Files: outputs are written whole or not at all (each goes to a
// temporary file in the same directory and is renamed into place); inputs
// are read whole.
#pragma once

#include <string>

namespace ipmc {

// Writes `content` to `path` atomically. Throws std::runtime_error naming
// the path on failure.
void WriteFileAtomically(const std::string& path, const std::string& content);

// Creates `dir` (and parents) if needed; throws naming the directory.
void EnsureDirectory(const std::string& dir);

// The whole content of `path`. Throws InputError (sim/io/error.h)
// "PATH: cannot open the WHAT" or "PATH: cannot read the WHAT".
std::string ReadTextFile(const std::string& path, const std::string& what);

}  // namespace ipmc
