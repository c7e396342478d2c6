// Files: outputs are written whole or not at all (each goes to a
// temporary file in the same directory and is renamed into place when
// complete, with the permissions of a new file); inputs are read whole.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace ipmc {

// An output file that is complete only when Commit() is called: it is
// written at temp_path() (by this program or by another one, such as
// gnuplot or ffmpeg), Commit() renames it to path(), and an object that
// goes without Commit() removes the temporary.
class PendingFile {
 public:
  // temp_path(): a new empty file "PATH.tmp.PID.XXXXXX" (unique; PID this
  // process). Removes PATH's temporaries left by processes that no longer
  // run.
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
  bool committed() const { return committed_; }

 private:
  std::string path_;
  std::string temp_path_;
  bool committed_ = false;
};

// Throws std::runtime_error "PATH: cannot replace it, it is a WHAT (...)" if
// something other than a regular file (or a symbolic link, which a rename
// replaces, not what it leads to) sits at `path`: a device, a FIFO, a
// socket or a directory is never swapped out by a rename nor written
// through. Nothing at `path` is fine. Every writer calls it before any work
// (RequireWritableParent) and again as it renames into place.
void RequireReplaceable(const std::string& path);

// Throws InputError (sim/base/error.h, kUnreadable) "PATH: is a WHAT,
// not a regular file (the WHAT_READ)" unless `path` leads to a regular
// file or to nothing (the caller reports a missing file its own way): a
// FIFO or a device would block or never end, a directory is no file.
void RequireRegularInput(const std::string& path, const std::string& what);

// Writes `content` to `path` atomically. Throws std::runtime_error naming
// the path on failure.
void WriteFileAtomically(const std::string& path, const std::string& content);

// Writes each (path, content) pair atomically, in order, and removes each
// of `stale` (files of the same set that this write does not make, so
// that no file of an older set stays beside the new ones), all of it or
// nothing: every temporary is written before the first is renamed into
// place (a table's CSV and JSON appear together), and if a rename or a
// removal fails every file is put back as it was before the call. Throws
// std::runtime_error naming the path that failed and the reason (also,
// before any change, if a path is a directory).
void WriteFilesTogether(const std::vector<std::pair<std::string, std::string>>& files,
                        const std::vector<std::string>& stale = {});

// Holds an output directory for one writer at a time (flock on the
// directory itself) for as long as it lives: two runs into one folder
// cannot mix their files, the second is refused at its start. Creates the
// directory (and parents) if needed, and removes what it created if it
// is still empty when released (a run that failed leaves nothing).
// Throws std::runtime_error "DIR: in use by another run (...)" or
// naming the reason it cannot be created or opened.
class DirectoryLock {
 public:
  explicit DirectoryLock(const std::string& dir);
  ~DirectoryLock();
  DirectoryLock(const DirectoryLock&) = delete;
  DirectoryLock& operator=(const DirectoryLock&) = delete;

 private:
  void Release();
  std::string dir_;
  std::vector<std::string> created_;  // the folders this lock made, deepest first
  int fd_ = -1;
};

// A journal: a file of records, one a line, that one writer at a time
// appends to and that outlives a killed run. Opened (created, with its
// folder, if missing; never through a symbolic link) with an exclusive
// flock held for as long as the object lives, on the file the name leads
// to (a journal that another writer unlinked between the open and the
// lock is let go and the name opened again). A file system without locks
// (ENOLCK) is let through: the user then keeps writers apart.
class JournalFile {
 public:
  // Throws std::runtime_error naming the path if it is a symbolic link or
  // not a regular file, cannot be opened, or another writer holds it
  // ("PATH: " + in_use).
  JournalFile(const std::string& path, const std::string& in_use);
  ~JournalFile();
  JournalFile(const JournalFile&) = delete;
  JournalFile& operator=(const JournalFile&) = delete;

  const std::string& path() const { return path_; }
  // The whole text, from the start.
  std::string Read() const;
  // Empties the file and writes `header`; returns once both it and the
  // file's directory entry are on the disk.
  void Reset(const std::string& header);
  // Keeps the first `size` bytes (drops a torn last record).
  void Truncate(size_t size);
  // Appends `text` and returns once it is on the disk (fdatasync).
  void Append(const std::string& text);
  // Unlinks the file, then lets go of the lock: no other writer can take
  // the lock on it while its name still leads to it.
  void Remove();
  // Remove(), and the folder the constructor created for it if it is
  // empty: for a new journal whose header could not be written, so that a
  // failed start leaves nothing behind.
  void Discard();

 private:
  std::string path_;
  std::string created_folder_;  // the parent folder the constructor made, or ""
  int fd_ = -1;
};

// The whole text of the journal at `path`, read without taking its lock
// (its writer may be appending), nullopt if there is none. Throws
// std::runtime_error naming the path for a symbolic link (a journal is
// never read through one, as JournalFile never writes through one) and
// InputError for anything but a regular file or a failed read.
std::optional<std::string> ReadJournalText(const std::string& path, const std::string& what);

// Throws std::invalid_argument "WHO: OPTION PATH would overwrite the
// input PATH" if `output` is (or names the same file as) one of `inputs`.
void RefuseOverwritingInputs(const std::string& who, const std::string& option,
                             const std::string& output, const std::vector<std::string>& inputs);

// Creates `dir` (and parents) if needed; throws naming the directory and
// the reason.
void EnsureDirectory(const std::string& dir);
// Whether `dir` can be made and written, before a run's work rather than
// after it: a probe file is created and removed in the nearest folder of
// `dir` that exists (nothing is left, nothing is created). Throws
// std::runtime_error "DIR: cannot write in the output directory (REASON)"
// or "DIR: cannot create output directory (...)".
// Throws also for an empty `dir`, and if a name in it is longer than the
// file system takes (or the path longer than PATH_MAX), "PATH: name too long ...".
void RequireWritableDirectory(const std::string& dir);
// The same for the directory of an output file PATH (its parent, or "."),
// and PATH itself: not empty, not a directory, and a name that fits with
// its temporary's suffix (and `longest_suffix`, for a prefix of names such
// as a table's PREFIX.journal); nothing but a regular file in its place
// (RequireReplaceable).
void RequireWritableParent(const std::string& path, const std::string& longest_suffix = "");
// The same for the directory `path` is in, if it names one.
void EnsureParentDirectory(const std::string& path);

// The whole content of `path`. Throws InputError (sim/base/error.h)
// "PATH: cannot open the WHAT", "PATH: cannot read the WHAT" or, for
// anything but a regular file, RequireRegularInput's.
std::string ReadTextFile(const std::string& path, const std::string& what);

}  // namespace ipmc
