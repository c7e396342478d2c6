// The one launcher (sim/io/process.h): programs run from an argument
// vector without a shell, their output captured or logged, their exit
// status and ending signal reported; ShellQuote and LastLine.
#include "sim/io/process.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/io/files.h"
#include "tests/cli_util.h"

namespace ipmc {
namespace {

namespace fs = std::filesystem;

fs::path FreshDir(const std::string& name) { return ipmc::testing::FreshDir("process_" + name); }

TEST(ProcessTest, CapturesOutputAndExitStatus) {
  const ProgramExit exit = RunProgram({"sh", "-c", "echo one; echo two >&2; exit 3"});
  EXPECT_EQ(exit.exit_code, 3);
  EXPECT_EQ(exit.signal, 0);
  EXPECT_FALSE(exit.ok());
  EXPECT_EQ(exit.output, "one\ntwo\n");
  EXPECT_EQ(exit.How(), "exit status 3");
  EXPECT_TRUE(RunProgram({"true"}).ok());
}

// Each element is one argument as it stands: no shell splits or expands it.
TEST(ProcessTest, ArgumentsReachTheProgramVerbatim) {
  const ProgramExit exit = RunProgram({"printf", "%s|", "a b", "it's", "$HOME", "*", ""});
  EXPECT_TRUE(exit.ok()) << exit.output;
  EXPECT_EQ(exit.output, "a b|it's|$HOME|*||");
}

TEST(ProcessTest, ReportsTheSignalThatEndedIt) {
  const ProgramExit exit = RunProgram({"sh", "-c", "kill -9 $$"});
  EXPECT_EQ(exit.exit_code, -1);
  EXPECT_EQ(exit.signal, 9);
  EXPECT_EQ(exit.How(), "killed by signal 9");
}

TEST(ProcessTest, WritesOutputAndErrorsToTheLog) {
  const fs::path log = FreshDir("log") / "program.log";
  const ProgramExit exit = RunProgram({"sh", "-c", "echo out; echo err >&2"}, log.string());
  EXPECT_TRUE(exit.ok());
  EXPECT_EQ(exit.output, "");
  EXPECT_EQ(ReadTextFile(log.string(), "log"), "out\nerr\n");
  EXPECT_EQ(LastLineOfFile(log.string()), "err");
}

TEST(ProcessTest, MissingProgramIsAnErrorNamingIt) {
  try {
    RunProgram({"ipmc-no-such-program"});
    ADD_FAILURE() << "expected an error";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("ipmc-no-such-program: cannot start"),
              std::string::npos)
        << error.what();
  }
  EXPECT_THROW(RunProgram({}), std::invalid_argument);
}

TEST(ProcessTest, FeedsItsInput) {
  const fs::path dir = FreshDir("input");
  ProgramIo io;
  io.write_input = true;
  io.log_path = (dir / "log").string();
  Program program({"sh", "-c", "cat > \"$0\"", (dir / "copy").string()}, io);
  const std::string text = "frame 1\nframe 2\n";
  EXPECT_TRUE(program.Write(text.data(), text.size()));
  EXPECT_TRUE(program.Wait().ok());
  EXPECT_EQ(ReadTextFile((dir / "copy").string(), "copy"), text);
  EXPECT_THROW(program.Wait(), std::logic_error);
  // Input without a log could deadlock on captured output: refused.
  EXPECT_THROW(Program({"cat"}, ProgramIo{true, ""}), std::invalid_argument);
}

// A program that stops reading makes Write return false instead of
// raising SIGPIPE in the caller.
TEST(ProcessTest, WriteToAProgramThatStoppedReadingFails) {
  const fs::path dir = FreshDir("stopped");
  ProgramIo io;
  io.write_input = true;
  io.log_path = (dir / "log").string();
  Program program({"true"}, io);
  const std::string block(1 << 20, 'x');
  bool written = true;
  for (int k = 0; k < 8 && written; ++k) written = program.Write(block.data(), block.size());
  EXPECT_FALSE(written);
  EXPECT_TRUE(program.Wait().ok());
}

TEST(ProcessTest, ShellQuoteReadsBackThroughAShell) {
  EXPECT_EQ(ShellQuote("it's"), "'it'\\''s'");
  const std::string word = "a b 'c' \"d\" $HOME `x` \\ *";
  const ProgramExit exit = RunProgram({"sh", "-c", "printf %s " + ShellQuote(word)});
  EXPECT_EQ(exit.output, word);
}

// A printed command's words are pasted safely: a plain path stays
// readable, anything the shell would expand or split is quoted, and a
// directory named $(...) runs nothing when the line is pasted.
TEST(ProcessTest, ShellWordQuotesOnlyWhatTheShellWouldChange) {
  EXPECT_EQ(ShellWord("/home/me/runs/lengths"), "/home/me/runs/lengths");
  EXPECT_EQ(ShellWord("a b"), "'a b'");
  EXPECT_EQ(ShellWord("-rf"), "'-rf'");
  EXPECT_EQ(ShellWord(""), "''");
  const std::string dir = "/tmp/$(touch ipmc_pwned)";
  EXPECT_EQ(ShellWord(dir), "'/tmp/$(touch ipmc_pwned)'");
  const ProgramExit exit = RunProgram({"sh", "-c", "printf %s " + ShellWord(dir)});
  EXPECT_EQ(exit.output, dir);
}

TEST(ProcessTest, LastLineIsTheLastNonBlankLine) {
  EXPECT_EQ(LastLine(""), "");
  EXPECT_EQ(LastLine("\n \n\t\n"), "");
  EXPECT_EQ(LastLine("first\n  second error\r\n\n  \n"), "second error");
  EXPECT_EQ(LastLine("no line end"), "no line end");
  EXPECT_EQ(LastLineOfFile("/nonexistent/ipmc_process_test"), "");
}

}  // namespace
}  // namespace ipmc
