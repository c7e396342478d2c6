// Writing rendered frames: PNG images and H.264 MP4 videos. Frames are
// 8-bit RGB, rows from top to bottom (width x height x 3 bytes), as
// OffscreenRenderer::Frame returns them.
//
// Like every output of ipmc-swim, a file is written whole or not at all
// (sim/io/files.h): PNGs go through WriteFileAtomically; the video is
// encoded into OUT.tmp.mp4 (a PendingFile) and renamed to OUT when ffmpeg
// has finished successfully.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "sim/io/files.h"
#include "sim/io/process.h"

namespace ipmc {

// Encodes rgb as a PNG file at path. Throws FieldError ("width", "height",
// "rgb") for a non-positive size or rgb not width x height x 3 bytes, std::runtime_error naming the path if it
// cannot be written.
void WritePng(const std::string& path, const std::vector<unsigned char>& rgb, int width,
              int height);

// Pipes raw frames to ffmpeg (from PATH, started from an argument vector,
// no shell; sim/io/process.h):
//   ffmpeg -y -f rawvideo -pix_fmt rgb24 -s WxH -r FPS -i -
//          -c:v libx264 -preset veryfast -pix_fmt yuv420p OUT.tmp.mp4
// with -nostdin, -loglevel error and -f mp4 added, and ffmpeg's output
// going to a temporary log next to OUT (its last line ends up in the error
// message). yuv420p needs an even width and height. The veryfast preset
// takes about a third of the default's CPU time (no trellis
// quantisation), which matters for filming alongside a run.
class Mp4Writer {
 public:
  // Starts ffmpeg. Throws FieldError ("width", "height", "fps") for an odd
  // or non-positive size or fps outside (0, 1000], std::runtime_error naming the file if ffmpeg cannot
  // be started.
  Mp4Writer(const std::string& path, int width, int height, double fps);
  // Without a successful Finish(): stops ffmpeg and removes the temporary
  // file, leaving no output.
  ~Mp4Writer();
  Mp4Writer(const Mp4Writer&) = delete;
  Mp4Writer& operator=(const Mp4Writer&) = delete;

  // Throws FieldError ("rgb") for a wrong frame size, std::runtime_error
  // naming the file (and ffmpeg's last message) if ffmpeg stopped.
  void AddFrame(const std::vector<unsigned char>& rgb);
  // Waits for ffmpeg and renames the video into place. Throws
  // std::runtime_error naming the file on failure or if no frame was added.
  void Finish();

  int frames() const { return frames_; }
  const std::string& path() const { return path_; }

 private:
  // Closes ffmpeg's input, waits and returns its exit status (-1 if it was
  // killed or is gone).
  int ClosePipe();
  // Removes ffmpeg's log and throws "OUT: what (ffmpeg's message)"; the
  // unfinished video goes with the writer.
  [[noreturn]] void Fail(const std::string& what);

  std::string path_;
  PendingFile output_;  // OUT.tmp.mp4, which ffmpeg writes
  std::string log_path_;
  int width_, height_;
  int frames_ = 0;
  std::unique_ptr<Program> ffmpeg_;  // writing OUT.tmp.mp4, its messages in the log
  bool finished_ = false;
};

}  // namespace ipmc
