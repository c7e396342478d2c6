#include "renders/video.h"

#include <pthread.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "sim/io/files.h"

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBI_WRITE_NO_STDIO
#include <stb/stb_image_write.h>

namespace ipmc {
namespace {

void CheckFrameSize(const std::vector<unsigned char>& rgb, int width, int height,
                    const std::string& what) {
  const size_t expected = static_cast<size_t>(width) * height * 3;
  if (rgb.size() != expected) {
    throw std::invalid_argument(what + ": frame has " + std::to_string(rgb.size()) +
                                " bytes, expected " + std::to_string(width) + "x" +
                                std::to_string(height) + "x3 = " + std::to_string(expected));
  }
}

void AppendBytes(void* context, void* data, int size) {
  static_cast<std::string*>(context)->append(static_cast<const char*>(data), size);
}

// A path as one word for /bin/sh: in single quotes, with each ' as '\''.
std::string ShellQuote(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) {
    if (c == '\'') {
      quoted += "'\\''";
    } else {
      quoted += c;
    }
  }
  return quoted + "'";
}

// Blocks SIGPIPE in this thread while writing to ffmpeg, so that a write
// to a pipe whose reader has died fails with EPIPE instead of killing the
// program; a SIGPIPE raised meanwhile is consumed before the mask is
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

// Removes path if it is a file (never a directory someone made there).
void RemoveFile(const std::string& path) {
  std::error_code error;
  if (std::filesystem::is_regular_file(path, error)) std::filesystem::remove(path, error);
}

// The last non-empty line of a file ("" if none).
std::string LastLine(const std::string& path) {
  std::ifstream in(path);
  std::string line, last;
  while (std::getline(in, line)) {
    if (line.find_first_not_of(" \t\r") != std::string::npos) last = line;
  }
  return last;
}

}  // namespace

void WritePng(const std::string& path, const std::vector<unsigned char>& rgb, int width,
              int height) {
  if (width <= 0 || height <= 0) {
    throw std::invalid_argument(path + ": image size must be positive");
  }
  CheckFrameSize(rgb, width, height, path);
  std::string png;
  if (!stbi_write_png_to_func(AppendBytes, &png, width, height, 3, rgb.data(), width * 3)) {
    throw std::runtime_error(path + ": PNG encoding failed");
  }
  WriteFileAtomically(path, png);
}

Mp4Writer::Mp4Writer(const std::string& path, int width, int height, double fps)
    : path_(path), output_(path, ".tmp.mp4"), width_(width), height_(height) {
  if (width <= 0 || height <= 0 || width % 2 != 0 || height % 2 != 0) {
    throw std::invalid_argument(path + ": video size must be positive and even for yuv420p (got " +
                                std::to_string(width) + "x" + std::to_string(height) + ")");
  }
  if (!(fps > 0.0 && fps <= 1000.0)) {
    std::ostringstream msg;
    msg << path << ": frame rate must be in (0, 1000] fps (got " << fps << ")";
    throw std::invalid_argument(msg.str());
  }
  std::string log = path + ".ffmpeg.XXXXXX";
  const int fd = mkstemp(log.data());
  if (fd < 0) {
    throw std::runtime_error(path + ": cannot create file (" + std::strerror(errno) + ")");
  }
  close(fd);
  log_path_ = log;

  std::ostringstream command;
  command.precision(12);
  command << "ffmpeg -nostdin -y -loglevel error -f rawvideo -pix_fmt rgb24 -s " << width << "x"
          << height << " -r " << fps << " -i - -c:v libx264 -preset veryfast -pix_fmt yuv420p -f mp4 "
          << ShellQuote(output_.temp_path()) << " 2>" << ShellQuote(log_path_);
  pipe_ = popen(command.str().c_str(), "w");
  if (!pipe_) {
    const std::string reason = std::strerror(errno);
    RemoveFile(log_path_);
    throw std::runtime_error(path + ": cannot start ffmpeg (" + reason + ")");
  }
}

Mp4Writer::~Mp4Writer() {
  if (finished_) return;
  ClosePipe();  // output_ then removes the unfinished video
  RemoveFile(log_path_);
}

int Mp4Writer::ClosePipe() {
  if (!pipe_) return -1;
  ScopedSigpipeBlock block;
  const int status = pclose(pipe_);
  pipe_ = nullptr;
  if (status == -1 || !WIFEXITED(status)) return -1;
  return WEXITSTATUS(status);
}

void Mp4Writer::Fail(const std::string& what) {
  ClosePipe();
  std::string message = path_ + ": " + what;
  const std::string ffmpeg_said = LastLine(log_path_);
  if (!ffmpeg_said.empty()) message += " (ffmpeg: " + ffmpeg_said + ")";
  RemoveFile(log_path_);
  finished_ = true;  // nothing left to clean up
  throw std::runtime_error(message);
}

void Mp4Writer::AddFrame(const std::vector<unsigned char>& rgb) {
  CheckFrameSize(rgb, width_, height_, path_);
  if (!pipe_ || finished_) throw std::runtime_error(path_ + ": video already closed");
  size_t written = 0;
  {
    ScopedSigpipeBlock block;
    written = std::fwrite(rgb.data(), 1, rgb.size(), pipe_);
  }
  if (written != rgb.size()) Fail("ffmpeg stopped reading frames");
  ++frames_;
}

void Mp4Writer::Finish() {
  if (finished_) throw std::runtime_error(path_ + ": video already finished");
  if (frames_ == 0) Fail("no frames to encode");
  const int status = ClosePipe();
  if (status != 0) {
    Fail(status < 0 ? "ffmpeg did not finish" : "ffmpeg failed with exit code " + std::to_string(status));
  }
  RemoveFile(log_path_);
  finished_ = true;
  output_.Commit();
}

}  // namespace ipmc
