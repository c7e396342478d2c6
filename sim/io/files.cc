#include "sim/io/files.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace ipmc {
namespace {

std::string Reason() { return std::strerror(errno); }

// The process's umask, read without changing it (umask(2) can only be read
// by setting it, which would race with other threads writing files).
mode_t CurrentUmask() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("Umask:", 0) == 0) return static_cast<mode_t>(std::stoul(line.substr(6), nullptr, 8));
  }
  return 022;
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

void WriteFileAtomically(const std::string& path, const std::string& content) {
  std::string temp = path + ".tmp.XXXXXX";
  const int fd = mkstemp(temp.data());
  if (fd < 0) throw std::runtime_error(path + ": cannot create file (" + Reason() + ")");
  // mkstemp creates the file 0600; outputs get the mode open(2) would give.
  const bool written = fchmod(fd, 0666 & ~CurrentUmask()) == 0 && WriteAll(fd, content);
  const std::string write_reason = written ? "" : Reason();
  const bool closed = close(fd) == 0;
  if (!written || !closed) {
    const std::string reason = written ? Reason() : write_reason;
    std::remove(temp.c_str());
    throw std::runtime_error(path + ": write failed (" + reason + ")");
  }
  if (std::rename(temp.c_str(), path.c_str()) != 0) {
    const std::string reason = Reason();
    std::remove(temp.c_str());
    throw std::runtime_error(path + ": cannot rename into place (" + reason + ")");
  }
}

void EnsureDirectory(const std::string& dir) {
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error || !std::filesystem::is_directory(dir)) {
    throw std::runtime_error(dir + ": cannot create output directory" +
                             (error ? " (" + error.message() + ")" : ""));
  }
}

}  // namespace ipmc
