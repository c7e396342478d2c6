// Running another program (sbatch, gnuplot, ffmpeg): from an argument
// vector, never through a shell, argv[0] looked up on PATH, its standard
// input /dev/null or a pipe the caller writes, its standard output and
// error together either captured or written to a log file. Also how a
// command is shown to a user who may paste it into a shell (ShellQuote)
// and how a program's message is picked from its output (LastLine).
#pragma once

#include <sys/types.h>

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace ipmc {

// How a program ended.
struct ProgramExit {
  int exit_code = -1;  // its exit status; -1 if a signal ended it
  int signal = 0;      // the signal that ended it; 0 if it exited
  std::string output;  // its stdout and stderr, when captured ("" with a log file)

  bool ok() const { return exit_code == 0; }
  // "exit status N" or "killed by signal N".
  std::string How() const;
};

// Where a started program's input comes from and its output goes.
struct ProgramIo {
  // Standard input: a pipe written with Program::Write, else /dev/null.
  bool write_input = false;
  // Standard output and error into this file (created or truncated);
  // "": captured into ProgramExit::output (not with write_input, which
  // could deadlock on a full pipe).
  std::string log_path;
};

// A running program. The destructor closes its input and waits for it.
class Program {
 public:
  // Starts argv. Throws std::invalid_argument for an empty argv or
  // write_input without a log, std::runtime_error "ARGV0: cannot start
  // (REASON)" if it cannot be started.
  Program(const std::vector<std::string>& argv, const ProgramIo& io);
  ~Program();
  Program(const Program&) = delete;
  Program& operator=(const Program&) = delete;

  // Writes all of `data` to the program's input; false if it stopped
  // reading (the program died or closed its input; SIGPIPE is blocked in
  // this thread meanwhile, so it never ends the caller).
  bool Write(const void* data, std::size_t size);
  // Closes the input, collects the captured output and waits for the
  // program to end. Once only; a second call throws std::logic_error.
  ProgramExit Wait();

 private:
  std::string name_;
  pid_t pid_ = -1;
  int input_fd_ = -1;
  int output_fd_ = -1;
  bool waited_ = false;
};

// Runs argv to its end with no input; its output captured, or written to
// `log_path` if given. Throws as Program does.
ProgramExit RunProgram(const std::vector<std::string>& argv, const std::string& log_path = "");

// `text` as one word for a POSIX shell: in single quotes, each ' as '\''.
// For printing commands (and writing scripts) a user may paste; programs
// are never started through a shell.
std::string ShellQuote(const std::string& text);
// The same, but a word the shell reads as it is (letters, digits and
// _./:=+,-%@, not starting with -) is left unquoted: for commands printed
// to be read as well as pasted.
std::string ShellWord(const std::string& text);

// The last line of `text` that is not blank, without its leading blanks
// and its line end; "" if there is none.
std::string LastLine(std::string_view text);
// LastLine of a file's content; "" if it cannot be read.
std::string LastLineOfFile(const std::string& path);

}  // namespace ipmc
