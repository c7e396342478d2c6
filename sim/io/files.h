// Files: outputs are written whole or not at all (each goes to a
// temporary file in the same directory and is renamed into place when
// complete, with the permissions of a new file); inputs are read whole.
#pragma once

#include <string>

namespace ipmc {

// An output file that is complete only when Commit() is called: it is
// written at temp_path() (by this program or by another one, such as
// gnuplot or ffmpeg), Commit() renames it to path(), and an object that
// goes without Commit() removes the temporary.
class PendingFile {
 public:
  // temp_path(): a new empty file "PATH.tmp.XXXXXX" (unique).
  explicit PendingFile(std::string path);
  // temp_path(): "PATH" + temp_suffix, not created (the writer makes it).
  PendingFile(std::string path, const std::string& temp_suffix);
  ~PendingFile();
  PendingFile(const PendingFile&) = delete;
  PendingFile& operator=(const PendingFile&) = delete;

  const std::string& path() const { return path_; }
  const std::string& temp_path() const { return temp_path_; }
  // Renames the temporary into place; throws std::runtime_error naming
  // the path.
  void Commit();

 private:
  std::string path_;
  std::string temp_path_;
  bool committed_ = false;
};

// Writes `content` to `path` atomically. Throws std::runtime_error naming
// the path on failure.
void WriteFileAtomically(const std::string& path, const std::string& content);

// Creates `dir` (and parents) if needed; throws naming the directory.
void EnsureDirectory(const std::string& dir);
// The same for the directory `path` is in, if it names one.
void EnsureParentDirectory(const std::string& path);

// The whole content of `path`. Throws InputError (sim/io/error.h)
// "PATH: cannot open the WHAT" or "PATH: cannot read the WHAT".
std::string ReadTextFile(const std::string& path, const std::string& what);

}  // namespace ipmc
