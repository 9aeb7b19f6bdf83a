#pragma once
// `--video out.mp4`: frames piped as raw RGB to ffmpeg when it is on PATH (any container and
// codec ffmpeg picks from the file name), else the built-in Y4M writer. The video is written
// under a temporary name and renamed when ffmpeg has finished successfully.
#include <sys/types.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "host/render/frame_sink.h"

namespace ardcell {

// The first executable `program` in the directories of $PATH.
std::optional<std::filesystem::path> find_on_path(const std::string& program);

class FfmpegPipeSink : public FrameSink {
 public:
  ~FfmpegPipeSink() override;
  // Starts `ffmpeg` reading width x height rgb24 frames at fps from a pipe.
  static Status start(const std::filesystem::path& ffmpeg, const std::filesystem::path& out,
                      int width, int height, int fps, std::unique_ptr<FfmpegPipeSink>& sink);
  Status write(const ImageRgb8& image, const FrameInfo& info) override;
  Status finish() override;
  std::string describe() const override { return out_.string(); }

 private:
  FfmpegPipeSink() = default;
  int close_and_wait();  // ffmpeg's exit status, or -1
  std::filesystem::path out_, temp_;
  int width_ = 0, height_ = 0;
  std::FILE* pipe_ = nullptr;
  pid_t pid_ = -1;
};

// The sink for --video PATH: a .y4m path gets the built-in writer; anything else goes through
// ffmpeg when it is on PATH, else falls back to PATH with the extension .y4m, and `note` says
// so in one line.
Status make_video_sink(const std::filesystem::path& path, int width, int height, int fps,
                       std::unique_ptr<FrameSink>& sink, std::string& note);

}  // namespace ardcell
