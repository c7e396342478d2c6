#include "sim/io/files.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <climits>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <utility>

#include "sim/base/error.h"

namespace ipmc {
namespace {

// The temporaries of PATH are "PATH.tmp.PID.XXXXXX": PID the process
// that writes it, so that one left by a process that no longer runs (a
// killed merge, a lost node) is known and removed by the next writer.
std::string TemporaryPrefix(const std::string& path) { return path + ".tmp."; }

// Removes PATH's temporaries whose process no longer runs.
void RemoveStaleTemporaries(const std::string& path) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  const fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  const std::string prefix = TemporaryPrefix(target.filename().string());
  std::error_code error;
  for (fs::directory_iterator it(dir, error), end; !error && it != end; it.increment(error)) {
    const std::string name = it->path().filename().string();
    if (name.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string rest = name.substr(prefix.size());
    const size_t dot = rest.find('.');
    if (dot == 0 || dot == std::string::npos ||
        rest.find_first_not_of("0123456789") != dot) {
      continue;  // not PID.XXXXXX
    }
    const long pid = std::strtol(rest.substr(0, dot).c_str(), nullptr, 10);
    if (pid <= 0 || pid == getpid()) continue;
    if (kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH && it->is_regular_file(error)) {
      std::error_code ignored;
      fs::remove(it->path(), ignored);
    }
  }
}

// Makes a new entry "PATH.tmp.PID.XXXXXX" (X: random letters and digits) with
// `make` (which returns false with errno EEXIST if the name is taken) and
// returns its name; throws naming `path` and the reason.
template <typename Make>
std::string MakeUniqueEntry(const std::string& path, Make make) {
  constexpr char kAlphabet[] = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789";
  constexpr int kAttempts = 100;
  std::random_device random;
  std::uniform_int_distribution<int> pick(0, static_cast<int>(sizeof(kAlphabet)) - 2);
  const std::string prefix = TemporaryPrefix(path) + std::to_string(getpid()) + ".";
  for (int attempt = 0; attempt < kAttempts; ++attempt) {
    std::string name = prefix;
    for (int i = 0; i < 6; ++i) name += kAlphabet[pick(random)];
    if (make(name)) return name;
    if (errno != EEXIST) break;
  }
  throw std::runtime_error(path + ": cannot create file (" + std::strerror(errno) + ")");
}

// Creates a new empty file "PATH.tmp.XXXXXX". Like mkstemp, but with the
// permissions of a new file (0666 less the umask) rather than 0600.
std::string CreateUniqueFile(const std::string& path) {
  return MakeUniqueEntry(path, [](const std::string& name) {
    const int fd = open(name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0) return false;
    close(fd);
    return true;
  });
}

// write(2) until every byte is out; false with errno set on failure.
bool WriteAll(int fd, const std::string& content) {
  const char* data = content.data();
  size_t left = content.size();
  while (left > 0) {
    const ssize_t n = write(fd, data, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    data += n;
    left -= static_cast<size_t>(n);
  }
  return true;
}

// What a non-regular file is, for messages: "a character device".
std::string FileKind(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISSOCK(mode)) return "a socket";
  return "a special file";
}

}  // namespace

void RequireReplaceable(const std::string& path) {
  struct stat status {};
  if (lstat(path.c_str(), &status) != 0) return;  // nothing there (or the writer says why)
  if (S_ISREG(status.st_mode) || S_ISLNK(status.st_mode)) return;
  throw std::runtime_error(path + ": cannot replace it, it is " + FileKind(status.st_mode) +
                           " (an output replaces only a regular file; name another)");
}

void RequireRegularInput(const std::string& path, const std::string& what) {
  struct stat status {};
  if (stat(path.c_str(), &status) != 0 || S_ISREG(status.st_mode)) return;
  throw InputError(InputProblem::kUnreadable, {path}, "",
                   "is " + FileKind(status.st_mode) + ", not a regular file (the " + what + ")");
}

PendingFile::PendingFile(std::string path) : path_(std::move(path)) {
  RequireReplaceable(path_);
  RemoveStaleTemporaries(path_);
  temp_path_ = CreateUniqueFile(path_);
}

PendingFile::PendingFile(std::string path, const std::string& temp_suffix)
    : path_(std::move(path)), temp_path_(path_ + temp_suffix) {
  RequireReplaceable(path_);
}

PendingFile::~PendingFile() {
  if (committed_) return;
  std::error_code error;
  if (std::filesystem::is_regular_file(temp_path_, error)) {
    std::filesystem::remove(temp_path_, error);
  }
}

void PendingFile::Commit() {
  RequireReplaceable(path_);
  if (std::rename(temp_path_.c_str(), path_.c_str()) != 0) {
    throw std::runtime_error(path_ + ": cannot rename into place (" + std::strerror(errno) + ")");
  }
  committed_ = true;
}

namespace {

// Writes `content` to the pending file's temporary; throws naming the
// file's path and the reason.
void WritePending(const PendingFile& file, const std::string& content) {
  const std::string& path = file.path();
  // Never through a symbolic link put in the temporary's place.
  const int fd = open(file.temp_path().c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC | O_NOFOLLOW);
  if (fd < 0) {
    throw std::runtime_error(path + ": cannot open for writing (" + std::strerror(errno) + ")");
  }
  const bool written = WriteAll(fd, content);
  const int write_errno = errno;
  const bool closed = close(fd) == 0;
  if (!written || !closed) {
    throw std::runtime_error(path + ": write failed (" +
                             std::strerror(written ? errno : write_errno) + ")");
  }
}

}  // namespace

void WriteFileAtomically(const std::string& path, const std::string& content) {
  PendingFile file(path);
  WritePending(file, content);
  file.Commit();
}

namespace {

// The files a write replaces or removes, kept as hard links until the
// write is whole ("PATH.tmp.XXXXXX"), so that a failure puts every one
// back as it was.
class Backups {
 public:
  ~Backups() {
    std::error_code error;
    for (const auto& [path, backup] : kept_) std::filesystem::remove(backup, error);
  }
  // Keeps `path` if it exists. Throws if it is something a file cannot
  // replace (a directory) or cannot be kept.
  void Keep(const std::string& path) {
    struct stat status {};
    if (lstat(path.c_str(), &status) != 0) return;  // nothing to keep
    RequireReplaceable(path);
    std::string backup;
    try {
      backup = MakeUniqueEntry(
          path, [&](const std::string& name) { return link(path.c_str(), name.c_str()) == 0; });
    } catch (const std::runtime_error&) {
      // An immutable or otherwise protected file cannot be linked, nor
      // replaced: say so before anything changes.
      throw std::runtime_error(path + ": cannot replace it (" + std::strerror(errno) + ")");
    }
    kept_.emplace_back(path, backup);
  }
  // Puts every kept file back in its place.
  void Restore() {
    for (const auto& [path, backup] : kept_) std::rename(backup.c_str(), path.c_str());
    kept_.clear();
  }

 private:
  std::vector<std::pair<std::string, std::string>> kept_;  // (path, backup)
};

}  // namespace

void WriteFilesTogether(const std::vector<std::pair<std::string, std::string>>& files,
                        const std::vector<std::string>& stale) {
  std::vector<std::unique_ptr<PendingFile>> pending;
  for (const auto& [path, content] : files) {
    pending.push_back(std::make_unique<PendingFile>(path));
    WritePending(*pending.back(), content);
  }
  Backups backups;
  for (const auto& file : pending) backups.Keep(file->path());
  for (const std::string& path : stale) backups.Keep(path);
  try {
    for (const auto& file : pending) file->Commit();
    for (const std::string& path : stale) {
      if (std::remove(path.c_str()) != 0 && errno != ENOENT) {
        throw std::runtime_error(path + ": cannot remove the previous run's file (" +
                                 std::strerror(errno) + ")");
      }
    }
  } catch (...) {
    // The new ones that are in place go, the old ones come back.
    std::error_code error;
    for (const auto& file : pending) {
      if (file->committed()) std::filesystem::remove(file->path(), error);
    }
    backups.Restore();
    throw;
  }
}

namespace {

enum class LockOutcome { kLocked, kHeldElsewhere, kUnsupported };

// flock(LOCK_EX | LOCK_NB) on `fd`, again when a signal interrupts it. A
// file system without locks (ENOLCK) is let through (kUnsupported): the
// user then keeps runs apart. Any other failure throws, naming `path`.
LockOutcome LockWithoutWaiting(int fd, const std::string& path) {
  for (;;) {
    if (flock(fd, LOCK_EX | LOCK_NB) == 0) return LockOutcome::kLocked;
    if (errno == EINTR) continue;
    if (errno == EWOULDBLOCK) return LockOutcome::kHeldElsewhere;
    if (errno == ENOLCK) return LockOutcome::kUnsupported;
    throw std::runtime_error(path + ": cannot lock (" + std::strerror(errno) + ")");
  }
}

}  // namespace

DirectoryLock::DirectoryLock(const std::string& dir) : dir_(dir) {
  namespace fs = std::filesystem;
  std::error_code error;
  fs::path folder = fs::absolute(dir, error).lexically_normal();
  if (folder.filename().empty()) folder = folder.parent_path();  // "out/run/"
  for (; !folder.empty() && !fs::exists(folder, error); folder = folder.parent_path()) {
    created_.push_back(folder.string());
  }
  try {
    EnsureDirectory(dir);
    fd_ = open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd_ < 0) {
      throw std::runtime_error(dir + ": cannot open output directory (" + std::strerror(errno) +
                               ")");
    }
    if (LockWithoutWaiting(fd_, dir) == LockOutcome::kHeldElsewhere) {
      throw std::runtime_error(dir + ": in use by another run (one run per output directory)");
    }
  } catch (...) {
    Release();
    throw;
  }
}

DirectoryLock::~DirectoryLock() { Release(); }

void DirectoryLock::Release() {
  // Removed while still held, so no other run has written into them; a
  // folder that holds anything stays.
  for (const std::string& folder : created_) rmdir(folder.c_str());
  created_.clear();
  if (fd_ >= 0) close(fd_);
  fd_ = -1;
}

namespace {

std::string SystemError(const std::string& path, const std::string& what) {
  return path + ": " + what + " (" + std::strerror(errno) + ")";
}

// The descriptor of the journal at `path`, open and locked (JournalFile).
int OpenLockedJournal(const std::string& path, const std::string& in_use) {
  for (;;) {
    const int fd = open(path.c_str(), O_RDWR | O_CREAT | O_APPEND | O_CLOEXEC | O_NOFOLLOW, 0644);
    if (fd < 0 && errno == ELOOP) {
      throw std::runtime_error(path + ": is a symbolic link; a journal is never written through "
                                      "one (remove it, or choose another output)");
    }
    if (fd < 0) throw std::runtime_error(SystemError(path, "cannot open the journal"));
    struct stat status {};
    if (fstat(fd, &status) != 0 || !S_ISREG(status.st_mode)) {
      close(fd);
      throw std::runtime_error(path + ": is not a regular file; a journal must be one");
    }
    try {
      if (LockWithoutWaiting(fd, path) == LockOutcome::kHeldElsewhere) {
        throw std::runtime_error(path + ": " + in_use);
      }
    } catch (...) {
      close(fd);
      throw;
    }
    struct stat named {};
    const bool still_named = stat(path.c_str(), &named) == 0 && named.st_ino == status.st_ino &&
                             named.st_dev == status.st_dev;
    if (still_named) return fd;
    close(fd);
  }
}

// The directory entry of a new file reaches the disk too.
void SyncDirectoryOf(const std::string& path) {
  std::string dir = std::filesystem::path(path).parent_path().string();
  if (dir.empty()) dir = ".";
  const int fd = open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  fsync(fd);
  close(fd);
}

}  // namespace

std::optional<std::string> ReadJournalText(const std::string& path, const std::string& what) {
  struct stat status {};
  if (lstat(path.c_str(), &status) != 0 && errno == ENOENT) return std::nullopt;
  if (S_ISLNK(status.st_mode)) {
    throw std::runtime_error(path + ": is a symbolic link; a journal is never read through one "
                                    "(copy the file in its place)");
  }
  return ReadTextFile(path, what);
}

JournalFile::JournalFile(const std::string& path, const std::string& in_use) : path_(path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  std::error_code error;
  if (!parent.empty() && !std::filesystem::exists(parent, error)) created_folder_ = parent.string();
  EnsureParentDirectory(path);
  fd_ = OpenLockedJournal(path, in_use);
}

JournalFile::~JournalFile() {
  if (fd_ >= 0) close(fd_);
}

std::string JournalFile::Read() const {
  std::string text;
  char buffer[1 << 16];
  for (off_t offset = 0;;) {
    const ssize_t n = pread(fd_, buffer, sizeof(buffer), offset);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw std::runtime_error(SystemError(path_, "cannot read the journal"));
    if (n == 0) return text;
    text.append(buffer, static_cast<size_t>(n));
    offset += n;
  }
}

void JournalFile::Reset(const std::string& header) {
  if (ftruncate(fd_, 0) != 0) {
    throw std::runtime_error(SystemError(path_, "cannot reset the journal"));
  }
  if (!WriteAll(fd_, header)) {
    throw std::runtime_error(SystemError(path_, "cannot write the journal"));
  }
  if (fsync(fd_) != 0) throw std::runtime_error(SystemError(path_, "cannot sync the journal"));
  SyncDirectoryOf(path_);
}

void JournalFile::Truncate(size_t size) {
  if (ftruncate(fd_, static_cast<off_t>(size)) != 0) {
    throw std::runtime_error(SystemError(path_, "cannot drop the torn last record"));
  }
}

void JournalFile::Append(const std::string& text) {
  if (!WriteAll(fd_, text)) {
    throw std::runtime_error(SystemError(path_, "cannot write the journal"));
  }
  if (fdatasync(fd_) != 0) throw std::runtime_error(SystemError(path_, "cannot sync the journal"));
}

void JournalFile::Remove() {
  std::remove(path_.c_str());
  if (fd_ >= 0) close(fd_);
  fd_ = -1;
}

void JournalFile::Discard() {
  Remove();
  std::error_code error;  // a folder that is not empty stays
  if (!created_folder_.empty()) std::filesystem::remove(created_folder_, error);
}

void RefuseOverwritingInputs(const std::string& who, const std::string& option,
                             const std::string& output, const std::vector<std::string>& inputs) {
  for (const std::string& input : inputs) {
    std::error_code error;
    const bool same = std::filesystem::equivalent(output, input, error);
    if (same || std::filesystem::path(output).lexically_normal() ==
                    std::filesystem::path(input).lexically_normal()) {
      throw std::invalid_argument(who + ": " + option + " " + output +
                                  " would overwrite the input " + input);
    }
  }
}

void EnsureDirectory(const std::string& dir) {
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error || !std::filesystem::is_directory(dir)) {
    const std::string reason = error ? error.message()
                                     : std::string("a file of that name is in the way");
    throw std::runtime_error(dir + ": cannot create output directory (" + reason + ")");
  }
}

namespace {

// The nearest folder of `path` that exists ("." if none is named).
std::filesystem::path NearestExisting(const std::string& path) {
  std::filesystem::path existing = std::filesystem::path(path).lexically_normal();
  std::error_code error;
  while (!existing.empty() && !std::filesystem::exists(existing, error)) {
    existing = existing.parent_path();
  }
  return existing.empty() ? std::filesystem::path(".") : existing;
}

// Throws std::runtime_error "PATH: name too long ..." if a part of `path`
// (the last with `last_suffix` appended, the longest name written for it)
// is longer than the file system takes, or the whole is longer than a
// path may be: such a name would fail only when the work is done.
void RequireNamesThatFit(const std::string& path, const std::filesystem::path& existing,
                         const std::string& last_suffix) {
  long name_max = pathconf(existing.c_str(), _PC_NAME_MAX);
  if (name_max <= 0) name_max = NAME_MAX;
  const std::filesystem::path parts = std::filesystem::path(path).lexically_normal();
  std::string last;
  for (const std::filesystem::path& part : parts) {
    if (!part.empty() && part != "/") last = part.string();
  }
  for (const std::filesystem::path& part : parts) {
    const std::string name = part.string();
    const size_t length = name.size() + (name == last ? last_suffix.size() : 0);
    if (length > static_cast<size_t>(name_max)) {
      throw std::runtime_error(
          path + ": name too long for the file system (" + std::to_string(name.size()) +
          " characters in '" + name.substr(0, 16) + "...'" +
          (last_suffix.empty() || name != last
               ? ""
               : ", " + std::to_string(last_suffix.size()) + " more for its temporary") +
          "; at most " + std::to_string(name_max) + ")");
    }
  }
  const std::string absolute = std::filesystem::absolute(parts).string() + last_suffix;
  if (absolute.size() >= PATH_MAX) {
    throw std::runtime_error(path + ": path too long (" + std::to_string(absolute.size()) +
                             " characters; at most " + std::to_string(PATH_MAX - 1) + ")");
  }
}

// The longest name a file PATH gets while being written: its temporary's suffix.
std::string TemporarySuffix() { return ".tmp." + std::to_string(getpid()) + ".XXXXXX"; }

}  // namespace

void RequireWritableDirectory(const std::string& dir) {
  if (dir.empty()) {
    throw std::runtime_error("cannot create output directory '' (an empty path; name a folder)");
  }
  // The nearest folder that exists must be one and take a new file; the
  // missing ones below it are made when the outputs are written.
  const std::filesystem::path existing = NearestExisting(dir);
  std::error_code error;
  RequireNamesThatFit(dir, existing, "");
  if (!std::filesystem::is_directory(existing, error)) {
    throw std::runtime_error(dir + ": cannot create output directory (" + existing.string() +
                             " is not a directory)");
  }
  try {
    const PendingFile probe((existing / ".ipmc_swim_probe").string());
  } catch (const std::runtime_error&) {
    throw std::runtime_error(dir + ": cannot write in the output directory (" +
                             std::strerror(errno) + ")");
  }
}

void RequireWritableParent(const std::string& path, const std::string& longest_suffix) {
  if (path.empty()) {
    throw std::runtime_error("cannot create file '' (an empty path; name a file)");
  }
  std::error_code error;
  if (path.back() == '/' || std::filesystem::is_directory(path, error)) {
    throw std::runtime_error(path + ": is a directory, not a file (name a file in it)");
  }
  RequireReplaceable(path);
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  RequireWritableDirectory(parent.empty() ? "." : parent.string());
  RequireNamesThatFit(path, NearestExisting(path), longest_suffix + TemporarySuffix());
}

void EnsureParentDirectory(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  if (!parent.empty()) EnsureDirectory(parent.string());
}

std::string ReadTextFile(const std::string& path, const std::string& what) {
  std::error_code status;
  if (std::filesystem::is_directory(path, status)) {
    throw InputError(InputProblem::kUnreadable, {path}, "", "is a directory, not the " + what);
  }
  RequireRegularInput(path, what);
  std::ifstream file(path, std::ios::binary);
  if (!file) throw InputError(InputProblem::kUnreadable, {path}, "", "cannot open the " + what);
  std::ostringstream text;
  text << file.rdbuf();
  if (file.bad()) {
    throw InputError(InputProblem::kUnreadable, {path}, "", "cannot read the " + what);
  }
  return text.str();
}

}  // namespace ipmc
