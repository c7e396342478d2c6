// Running the ipmc-swim program from tests.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

namespace ipmc::testing {

struct CommandResult {
  int exit_code;
  std::string output;  // stdout and stderr
};

// Runs `ipmc-swim ARGS` through the shell and captures its output;
// `prefix` goes before the program (environment settings, a wrapper).
inline CommandResult RunCli(const std::string& args, const std::string& prefix = "") {
  const std::string command = prefix + std::string(IPMC_SWIM_CLI) + " " + args + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  std::string output;
  char buffer[4096];
  while (size_t n = fread(buffer, 1, sizeof(buffer), pipe)) output.append(buffer, n);
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

// The scratch directories this process made (FreshDir), removed with
// everything in them when the process exits, whatever the tests' outcome.
class ScratchDirs {
 public:
  static ScratchDirs& Instance() {
    static ScratchDirs dirs;
    return dirs;
  }
  void Add(const std::filesystem::path& dir) {
    const std::lock_guard<std::mutex> lock(mutex_);
    dirs_.push_back(dir);
  }
  ~ScratchDirs() {
    std::error_code ignored;
    for (const std::filesystem::path& dir : dirs_) std::filesystem::remove_all(dir, ignored);
  }

 private:
  ScratchDirs() = default;
  std::mutex mutex_;
  std::vector<std::filesystem::path> dirs_;
};

// An empty directory under the test's temporary directory, private to
// this process (CTest runs the tests of one suite in parallel processes),
// removed when the process exits.
inline std::filesystem::path FreshDir(const std::string& name) {
  const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) /
                                    ("ipmc_" + name + "_" + std::to_string(getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  ScratchDirs::Instance().Add(dir);
  return dir;
}

inline int CountLines(const std::string& text) {
  int lines = 0;
  for (char c : text) lines += c == '\n';
  return lines;
}

// The whole content of a file (empty if it cannot be read).
inline std::string ReadFile(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

inline void WriteFile(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path) << text;
}

// A scenario of one wave period at 0.5 ms steps on the shipped flagellum:
// 0.1 s of CPU at `frequency_Hz` = 0.5 (4000 steps); slower waves run
// longer.
inline std::string OneCycleScenario(double frequency_Hz) {
  return "model = \"" +
         (std::filesystem::path(IPMC_SWIM_SOURCE_DIR) / "models" / "flagellum3.xml").string() +
         "\"\n"
         "actuation = \"distributed\"\n"
         "cycles = 1\n"
         "timestep_s = 5e-4\n"
         "[waveform]\n"
         "frequency_Hz = " + std::to_string(frequency_Hz) + "\n";
}

}  // namespace ipmc::testing
