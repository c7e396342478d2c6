#include "renders/video.h"

#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "sim/base/error.h"
#include "sim/io/files.h"
#include "sim/io/process.h"

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBI_WRITE_NO_STDIO
#include <stb/stb_image_write.h>

namespace ipmc {
namespace {

// `path` as ffmpeg must read it: a plain file, never a protocol
// ("tcp://...", "http://...", "pipe:1") or an option ("-x.mp4"). The
// file: protocol with an absolute path is read only as the file it names.
std::string FfmpegFileUrl(const std::string& path) {
  return "file:" + std::filesystem::absolute(path).lexically_normal().string();
}

void CheckFrameSize(const std::vector<unsigned char>& rgb, int width, int height,
                    const std::string& what) {
  const size_t expected = static_cast<size_t>(width) * height * 3;
  if (rgb.size() != expected) {
    throw FieldError(what + ": frame has " + std::to_string(rgb.size()) + " bytes, expected " +
                         std::to_string(width) + "x" + std::to_string(height) + "x3 = " +
                         std::to_string(expected),
                     "rgb", "width x height x 3 bytes");
  }
}

void AppendBytes(void* context, void* data, int size) {
  static_cast<std::string*>(context)->append(static_cast<const char*>(data), size);
}

// Removes path if it is a file (never a directory someone made there).
void RemoveFile(const std::string& path) {
  std::error_code error;
  if (std::filesystem::is_regular_file(path, error)) std::filesystem::remove(path, error);
}

// Whether `path` is a whole MP4: top-level boxes (4-byte big-endian size,
// 4-byte type) that tile the file exactly, among them "ftyp" and "moov"
// (ffmpeg writes moov last; a full disk can leave a file without it, and
// ffmpeg may still exit 0).
bool IsCompleteMp4(const std::string& path) {
  std::ifstream file(path, std::ios::binary | std::ios::ate);
  if (!file) return false;
  const std::uint64_t length = static_cast<std::uint64_t>(file.tellg());
  file.seekg(0);
  bool ftyp = false, moov = false;
  std::uint64_t offset = 0;
  while (offset + 8 <= length) {
    unsigned char header[16];
    file.seekg(static_cast<std::streamoff>(offset));
    if (!file.read(reinterpret_cast<char*>(header), 8)) return false;
    std::uint64_t size = (std::uint64_t{header[0]} << 24) | (std::uint64_t{header[1]} << 16) |
                         (std::uint64_t{header[2]} << 8) | header[3];
    const std::string type(reinterpret_cast<const char*>(header) + 4, 4);
    if (size == 1) {  // 64-bit size after the type
      if (!file.read(reinterpret_cast<char*>(header + 8), 8)) return false;
      size = 0;
      for (int i = 8; i < 16; ++i) size = (size << 8) | header[i];
    } else if (size == 0) {  // to the end of the file
      size = length - offset;
    }
    if (size < 8 || offset + size > length) return false;
    ftyp = ftyp || type == "ftyp";
    moov = moov || type == "moov";
    offset += size;
  }
  return offset == length && ftyp && moov;
}

}  // namespace

void WritePng(const std::string& path, const std::vector<unsigned char>& rgb, int width,
              int height) {
  if (width <= 0 || height <= 0) {
    throw FieldError(path + ": image size must be positive (got " + std::to_string(width) + "x" +
                         std::to_string(height) + ")",
                     width <= 0 ? "width" : "height", "> 0");
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
    throw FieldError(path + ": video size must be positive and even for yuv420p (got " +
                         std::to_string(width) + "x" + std::to_string(height) + ")",
                     width <= 0 || width % 2 != 0 ? "width" : "height", "even and > 0");
  }
  if (!(fps > 0.0 && fps <= 1000.0)) {
    std::ostringstream msg;
    msg << path << ": frame rate must be in (0, 1000] fps (got " << fps << ")";
    throw FieldError(msg.str(), "fps", "in (0, 1000]");
  }
  std::string log = path + ".ffmpeg.XXXXXX";
  const int fd = mkstemp(log.data());
  if (fd < 0) {
    throw std::runtime_error(path + ": cannot create file (" + std::strerror(errno) + ")");
  }
  close(fd);
  log_path_ = log;

  std::ostringstream rate;
  rate.precision(12);
  rate << fps;
  const std::vector<std::string> argv = {
      "ffmpeg", "-nostdin", "-y", "-loglevel", "error", "-f", "rawvideo", "-pix_fmt", "rgb24",
      "-s", std::to_string(width) + "x" + std::to_string(height), "-r", rate.str(), "-i", "-",
      "-c:v", "libx264", "-preset", "veryfast", "-pix_fmt", "yuv420p", "-f", "mp4",
      FfmpegFileUrl(output_.temp_path())};
  ProgramIo io;
  io.write_input = true;
  io.log_path = log_path_;
  try {
    ffmpeg_ = std::make_unique<Program>(argv, io);
  } catch (const std::runtime_error& error) {
    RemoveFile(log_path_);
    throw std::runtime_error(path + ": cannot start ffmpeg (" + error.what() + ")");
  }
}

Mp4Writer::~Mp4Writer() {
  if (finished_) return;
  ClosePipe();  // output_ then removes the unfinished video
  RemoveFile(log_path_);
}

int Mp4Writer::ClosePipe() {
  if (!ffmpeg_) return -1;
  const ProgramExit exit = ffmpeg_->Wait();
  ffmpeg_.reset();
  return exit.exit_code;
}

void Mp4Writer::Fail(const std::string& what) {
  ClosePipe();
  std::string message = path_ + ": " + what;
  const std::string ffmpeg_said = LastLineOfFile(log_path_);
  if (!ffmpeg_said.empty()) message += " (ffmpeg: " + ffmpeg_said + ")";
  RemoveFile(log_path_);
  finished_ = true;  // nothing left to clean up
  throw std::runtime_error(message);
}

void Mp4Writer::AddFrame(const std::vector<unsigned char>& rgb) {
  CheckFrameSize(rgb, width_, height_, path_);
  if (!ffmpeg_ || finished_) throw std::runtime_error(path_ + ": video already closed");
  if (!ffmpeg_->Write(rgb.data(), rgb.size())) Fail("ffmpeg stopped reading frames");
  ++frames_;
}

void Mp4Writer::Finish() {
  if (finished_) throw std::runtime_error(path_ + ": video already finished");
  if (frames_ == 0) Fail("no frames to encode");
  const int status = ClosePipe();
  if (status != 0) {
    Fail(status < 0 ? "ffmpeg did not finish" : "ffmpeg failed with exit code " + std::to_string(status));
  }
  if (!IsCompleteMp4(output_.temp_path())) {
    Fail("ffmpeg wrote an incomplete video (a full disk or a file size limit?)");
  }
  RemoveFile(log_path_);
  finished_ = true;
  output_.Commit();
}

}  // namespace ipmc
