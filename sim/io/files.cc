#include "sim/io/files.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <utility>

#include "sim/io/error.h"

namespace ipmc {
namespace {

// Makes a new entry "PATH.tmp.XXXXXX" (X: random letters and digits) with
// `make` (which returns false with errno EEXIST if the name is taken) and
// returns its name; throws naming `path` and the reason.
template <typename Make>
std::string MakeUniqueEntry(const std::string& path, Make make) {
  constexpr char kAlphabet[] = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789";
  constexpr int kAttempts = 100;
  std::random_device random;
  std::uniform_int_distribution<int> pick(0, static_cast<int>(sizeof(kAlphabet)) - 2);
  for (int attempt = 0; attempt < kAttempts; ++attempt) {
    std::string name = path + ".tmp.";
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

}  // namespace

PendingFile::PendingFile(std::string path) : path_(std::move(path)) {
  temp_path_ = CreateUniqueFile(path_);
}

PendingFile::PendingFile(std::string path, const std::string& temp_suffix)
    : path_(std::move(path)), temp_path_(path_ + temp_suffix) {}

PendingFile::~PendingFile() {
  if (committed_) return;
  std::error_code error;
  if (std::filesystem::is_regular_file(temp_path_, error)) {
    std::filesystem::remove(temp_path_, error);
  }
}

void PendingFile::Commit() {
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
    if (S_ISDIR(status.st_mode)) {
      throw std::runtime_error(path + ": cannot replace it, it is a directory");
    }
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
    // A file system without locks (ENOLCK) is let through: the user then
    // keeps runs apart.
    if (flock(fd_, LOCK_EX | LOCK_NB) != 0 && errno == EWOULDBLOCK) {
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

void RequireWritableDirectory(const std::string& dir) {
  // The nearest folder that exists must be one and take a new file; the
  // missing ones below it are made when the outputs are written.
  std::filesystem::path existing = std::filesystem::path(dir).lexically_normal();
  std::error_code error;
  while (!existing.empty() && !std::filesystem::exists(existing, error)) {
    existing = existing.parent_path();
  }
  if (existing.empty()) existing = ".";
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

void RequireWritableParent(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  RequireWritableDirectory(parent.empty() ? "." : parent.string());
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
