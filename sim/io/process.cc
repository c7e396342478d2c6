#include "sim/io/process.h"

#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <ctime>
#include <fstream>
#include <sstream>
#include <stdexcept>

extern char** environ;

namespace ipmc {
namespace {

// Blocks SIGPIPE in this thread while writing to a program, so that a
// write to a pipe whose reader has died fails with EPIPE instead of ending
// the caller; a SIGPIPE raised meanwhile is consumed before the mask is
// restored. The process's signal dispositions are left alone.
class ScopedSigpipeBlock {
 public:
  ScopedSigpipeBlock() {
    sigemptyset(&sigpipe_);
    sigaddset(&sigpipe_, SIGPIPE);
    pthread_sigmask(SIG_BLOCK, &sigpipe_, &previous_);
    sigset_t pending;
    sigpending(&pending);
    was_pending_ = sigismember(&pending, SIGPIPE) == 1;
  }
  ~ScopedSigpipeBlock() {
    if (!was_pending_) {
      sigset_t pending;
      sigpending(&pending);
      if (sigismember(&pending, SIGPIPE) == 1) {
        const timespec no_wait = {0, 0};
        sigtimedwait(&sigpipe_, nullptr, &no_wait);
      }
    }
    pthread_sigmask(SIG_SETMASK, &previous_, nullptr);
  }
  ScopedSigpipeBlock(const ScopedSigpipeBlock&) = delete;
  ScopedSigpipeBlock& operator=(const ScopedSigpipeBlock&) = delete;

 private:
  sigset_t sigpipe_, previous_;
  bool was_pending_ = false;
};

void CloseFd(int& fd) {
  if (fd >= 0) close(fd);
  fd = -1;
}

// Spawn actions and pipes, released on every path.
struct SpawnSetup {
  posix_spawn_file_actions_t actions;
  int input[2] = {-1, -1};
  int output[2] = {-1, -1};
  SpawnSetup() { posix_spawn_file_actions_init(&actions); }
  ~SpawnSetup() {
    posix_spawn_file_actions_destroy(&actions);
    for (int* fd : {&input[0], &input[1], &output[0], &output[1]}) CloseFd(*fd);
  }
};

}  // namespace

std::string ProgramExit::How() const {
  return signal != 0 ? "killed by signal " + std::to_string(signal)
                     : "exit status " + std::to_string(exit_code);
}

Program::Program(const std::vector<std::string>& argv, const ProgramIo& io) {
  if (argv.empty()) throw std::invalid_argument("Program: empty argument vector");
  if (io.write_input && io.log_path.empty()) {
    throw std::invalid_argument(argv[0] + ": a program that is written to needs a log file");
  }
  name_ = argv[0];
  SpawnSetup setup;
  if (io.write_input) {
    if (pipe2(setup.input, O_CLOEXEC) != 0) {
      throw std::runtime_error(name_ + ": cannot create a pipe (" + std::strerror(errno) + ")");
    }
    posix_spawn_file_actions_adddup2(&setup.actions, setup.input[0], STDIN_FILENO);
  } else {
    posix_spawn_file_actions_addopen(&setup.actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  }
  if (io.log_path.empty()) {
    if (pipe2(setup.output, O_CLOEXEC) != 0) {
      throw std::runtime_error(name_ + ": cannot create a pipe (" + std::strerror(errno) + ")");
    }
    posix_spawn_file_actions_adddup2(&setup.actions, setup.output[1], STDOUT_FILENO);
  } else {
    posix_spawn_file_actions_addopen(&setup.actions, STDOUT_FILENO, io.log_path.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0644);
  }
  posix_spawn_file_actions_adddup2(&setup.actions, STDOUT_FILENO, STDERR_FILENO);
  std::vector<char*> args;
  for (const std::string& arg : argv) args.push_back(const_cast<char*>(arg.c_str()));
  args.push_back(nullptr);
  const int spawned = posix_spawnp(&pid_, args[0], &setup.actions, nullptr, args.data(), environ);
  if (spawned != 0) {
    throw std::runtime_error(name_ + ": cannot start (" + std::strerror(spawned) + ")");
  }
  // Keep the parent's ends; the setup closes the child's.
  std::swap(input_fd_, setup.input[1]);
  std::swap(output_fd_, setup.output[0]);
}

Program::~Program() {
  if (!waited_) {
    try {
      Wait();
    } catch (...) {
    }
  }
}

bool Program::Write(const void* data, std::size_t size) {
  if (input_fd_ < 0) return false;
  ScopedSigpipeBlock block;
  const char* bytes = static_cast<const char*>(data);
  while (size > 0) {
    const ssize_t n = write(input_fd_, bytes, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    bytes += n;
    size -= static_cast<std::size_t>(n);
  }
  return true;
}

ProgramExit Program::Wait() {
  if (waited_) throw std::logic_error(name_ + ": waited for twice");
  waited_ = true;
  ProgramExit exit;
  {
    ScopedSigpipeBlock block;
    CloseFd(input_fd_);
  }
  if (output_fd_ >= 0) {
    char buffer[4096];
    for (;;) {
      const ssize_t n = read(output_fd_, buffer, sizeof(buffer));
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) break;
      exit.output.append(buffer, static_cast<std::size_t>(n));
    }
    CloseFd(output_fd_);
  }
  int status = 0;
  while (waitpid(pid_, &status, 0) < 0) {
    if (errno != EINTR) {
      throw std::runtime_error(name_ + ": waiting for it failed (" + std::strerror(errno) + ")");
    }
  }
  if (WIFEXITED(status)) {
    exit.exit_code = WEXITSTATUS(status);
  } else if (WIFSIGNALED(status)) {
    exit.signal = WTERMSIG(status);
  }
  return exit;
}

ProgramExit RunProgram(const std::vector<std::string>& argv, const std::string& log_path) {
  ProgramIo io;
  io.log_path = log_path;
  return Program(argv, io).Wait();
}

std::string ShellQuote(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

std::string ShellWord(const std::string& text) {
  const bool plain = !text.empty() && std::all_of(text.begin(), text.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || std::strchr("_./:=+,-%@", c) != nullptr;
  });
  return plain && text[0] != '-' ? text : ShellQuote(text);
}

std::string LastLine(std::string_view text) {
  std::string last;
  std::istringstream in{std::string(text)};
  std::string line;
  while (std::getline(in, line)) {
    const std::size_t start = line.find_first_not_of(" \t\r");
    if (start == std::string::npos) continue;
    const std::size_t end = line.find_last_not_of("\r");
    last = line.substr(start, end + 1 - start);
  }
  return last;
}

std::string LastLineOfFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return LastLine(text.str());
}

}  // namespace ipmc
