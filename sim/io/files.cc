#include "sim/io/files.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "sim/io/error.h"

namespace ipmc {

void WriteFileAtomically(const std::string& path, const std::string& content) {
  std::string temp = path + ".tmp.XXXXXX";
  const int fd = mkstemp(temp.data());
  if (fd < 0) throw std::runtime_error(path + ": cannot create file (" + std::strerror(errno) + ")");
  close(fd);
  {
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    out << content;
    out.flush();
    if (!out) {
      std::remove(temp.c_str());
      throw std::runtime_error(path + ": write failed");
    }
  }
  if (std::rename(temp.c_str(), path.c_str()) != 0) {
    std::remove(temp.c_str());
    throw std::runtime_error(path + ": cannot rename into place (" + std::strerror(errno) + ")");
  }
}

void EnsureDirectory(const std::string& dir) {
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error || !std::filesystem::is_directory(dir)) {
    throw std::runtime_error(dir + ": cannot create output directory");
  }
}

std::string ReadTextFile(const std::string& path, const std::string& what) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw InputError(InputProblem::kUnreadable, {path}, "", "cannot open the " + what);
  std::ostringstream text;
  text << file.rdbuf();
  if (file.bad()) throw InputError(InputProblem::kUnreadable, {path}, "", "cannot read the " + what);
  return text.str();
}

}  // namespace ipmc
