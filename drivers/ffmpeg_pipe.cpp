#include "drivers/ffmpeg_pipe.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <vector>

#include "drivers/y4m_writer.h"
#include "host/io/atomic_file.h"

extern char** environ;

namespace ardcell {

std::optional<std::filesystem::path> find_on_path(const std::string& program) {
  const char* path = std::getenv("PATH");
  if (!path || program.empty()) return std::nullopt;
  std::string_view rest(path);
  while (true) {
    const std::size_t colon = rest.find(':');
    std::string_view dir = rest.substr(0, colon);
    if (!dir.empty()) {
      std::filesystem::path candidate = std::filesystem::path(dir) / program;
      std::error_code ec;
      if (std::filesystem::is_regular_file(candidate, ec) && ::access(candidate.c_str(), X_OK) == 0)
        return candidate;
    }
    if (colon == std::string_view::npos) break;
    rest.remove_prefix(colon + 1);
  }
  return std::nullopt;
}

FfmpegPipeSink::~FfmpegPipeSink() {
  if (pipe_ || pid_ > 0) {
    close_and_wait();
    ::unlink(temp_.c_str());  // never finished: no partial video
  }
}

Status FfmpegPipeSink::start(const std::filesystem::path& ffmpeg, const std::filesystem::path& out,
                             int width, int height, int fps,
                             std::unique_ptr<FfmpegPipeSink>& sink) {
  std::unique_ptr<FfmpegPipeSink> s(new FfmpegPipeSink());
  s->out_ = out;
  // Keep the extension: ffmpeg picks the container from it.
  s->temp_ = temporary_sibling(out);
  s->temp_ += out.extension();
  s->width_ = width;
  s->height_ = height;
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0)
    return Status::error("--video: cannot create a pipe (" + errno_text(errno) + ")");
  const std::string size = std::to_string(width) + "x" + std::to_string(height);
  const std::string rate = std::to_string(fps);
  std::vector<std::string> args = {
      ffmpeg.string(), "-hide_banner", "-loglevel", "error", "-y", "-f", "rawvideo",
      "-pixel_format", "rgb24", "-video_size", size, "-framerate", rate, "-i", "-",
      // yuv420p (what players expect) needs even sides.
      "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-pix_fmt", "yuv420p", s->temp_.string()};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, fds[0], STDIN_FILENO);
  const int rc = ::posix_spawn(&s->pid_, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(fds[0]);
  if (rc != 0) {
    ::close(fds[1]);
    s->pid_ = -1;
    return Status::error("--video: cannot start " + ffmpeg.string() + " (" + errno_text(rc) + ")");
  }
  s->pipe_ = ::fdopen(fds[1], "wb");
  if (!s->pipe_) {
    ::close(fds[1]);
    return Status::error("--video: cannot open the pipe to ffmpeg");
  }
  sink = std::move(s);
  return Status::ok();
}

Status FfmpegPipeSink::write(const ImageRgb8& image, const FrameInfo&) {
  if (!pipe_) return Status::error(out_.string() + ": ffmpeg is not running");
  if (image.width != width_ || image.height != height_)
    return Status::error(out_.string() + ": frame size changed within one video");
  if (std::fwrite(image.rgb.data(), 1, image.rgb.size(), pipe_) != image.rgb.size()) {
    const int status = close_and_wait();
    return Status::error(out_.string() + ": ffmpeg stopped reading frames (exit status " +
                         std::to_string(status) + ")");
  }
  return Status::ok();
}

int FfmpegPipeSink::close_and_wait() {
  if (pipe_) {
    std::fclose(pipe_);
    pipe_ = nullptr;
  }
  int status = -1;
  if (pid_ > 0) {
    int wstatus = 0;
    while (::waitpid(pid_, &wstatus, 0) < 0 && errno == EINTR) {
    }
    pid_ = -1;
    status = WIFEXITED(wstatus) ? WEXITSTATUS(wstatus) : 128 + WTERMSIG(wstatus);
  }
  return status;
}

Status FfmpegPipeSink::finish() {
  const int status = close_and_wait();
  if (status != 0) {
    ::unlink(temp_.c_str());
    return Status::error(out_.string() + ": ffmpeg failed (exit status " + std::to_string(status) +
                         ")");
  }
  if (::rename(temp_.c_str(), out_.c_str()) != 0) {
    const int err = errno;
    ::unlink(temp_.c_str());
    return Status::error(out_.string() + ": cannot rename the finished video (" + errno_text(err) +
                         ")");
  }
  return Status::ok();
}

Status make_video_sink(const std::filesystem::path& path, int width, int height, int fps,
                       std::unique_ptr<FrameSink>& sink, std::string& note) {
  note.clear();
  if (path.extension() == ".y4m") {
    sink = std::make_unique<Y4mFileSink>(path, width, height, fps);
    return Status::ok();
  }
  if (std::optional<std::filesystem::path> ffmpeg = find_on_path("ffmpeg")) {
    std::unique_ptr<FfmpegPipeSink> pipe;
    if (Status s = FfmpegPipeSink::start(*ffmpeg, path, width, height, fps, pipe); !s) return s;
    sink = std::move(pipe);
    return Status::ok();
  }
  std::filesystem::path fallback = path;
  fallback.replace_extension(".y4m");
  note = "--video " + path.string() + ": ffmpeg not found on PATH; writing " + fallback.string() +
         " (YUV4MPEG2) instead";
  sink = std::make_unique<Y4mFileSink>(fallback, width, height, fps);
  return Status::ok();
}

}  // namespace ardcell
