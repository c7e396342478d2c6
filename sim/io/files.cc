#include "sim/io/files.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <utility>

#include "sim/io/error.h"

namespace ipmc {
namespace {

// Creates a new empty file "PATH.tmp.XXXXXX" (X: random letters and
// digits) and returns its name. Like mkstemp, but with the permissions of
// a new file (0666 less the umask) rather than 0600.
std::string CreateUniqueFile(const std::string& path) {
  constexpr char kAlphabet[] = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789";
  constexpr int kAttempts = 100;
  std::random_device random;
  std::uniform_int_distribution<int> pick(0, static_cast<int>(sizeof(kAlphabet)) - 2);
  for (int attempt = 0; attempt < kAttempts; ++attempt) {
    std::string name = path + ".tmp.";
    for (int i = 0; i < 6; ++i) name += kAlphabet[pick(random)];
    const int fd = open(name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) {
      close(fd);
      return name;
    }
    if (errno != EEXIST) break;
  }
  throw std::runtime_error(path + ": cannot create file (" + std::strerror(errno) + ")");
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

void WriteFileAtomically(const std::string& path, const std::string& content) {
  PendingFile file(path);
  const int fd = open(file.temp_path().c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
  if (fd < 0) throw std::runtime_error(path + ": cannot open for writing (" + std::strerror(errno) + ")");
  const bool written = WriteAll(fd, content);
  const int write_errno = errno;
  const bool closed = close(fd) == 0;
  if (!written || !closed) {
    throw std::runtime_error(path + ": write failed (" + std::strerror(written ? errno : write_errno) + ")");
  }
  file.Commit();
}

void EnsureDirectory(const std::string& dir) {
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error || !std::filesystem::is_directory(dir)) {
    throw std::runtime_error(dir + ": cannot create output directory");
  }
}

void EnsureParentDirectory(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  if (!parent.empty()) EnsureDirectory(parent.string());
}

std::string ReadTextFile(const std::string& path, const std::string& what) {
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
