#include "host/io/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>

namespace ardcell {

std::string errno_text(int err) { return std::strerror(err); }

Status check_output_path(const std::filesystem::path& path, bool folder) {
  namespace fs = std::filesystem;
  const char* expected = folder ? "a folder to write into" : "a file name to write";
  if (path.empty()) return Status::error(std::string("empty path (expected ") + expected + ")");
  const std::string what = path.string();
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0) {
    if (folder && !S_ISDIR(st.st_mode))
      return Status::error(what + ": exists and is not a folder (expected " + expected + ")");
    if (!folder && S_ISDIR(st.st_mode))
      return Status::error(what + ": is a folder (expected " + expected + ")");
    if (!folder && !S_ISREG(st.st_mode))
      return Status::error(what + ": is not a regular file (expected " + expected + ")");
    if (folder && ::access(path.c_str(), W_OK | X_OK) != 0)
      return Status::error(what + ": folder is not writable (" + errno_text(errno) + "; expected " +
                           expected + ")");
    if (folder) return Status::ok();
  }
  // The folder that will hold it: the parent, or the nearest ancestor that exists.
  fs::path parent = fs::absolute(path).lexically_normal();
  if (parent.filename().empty()) parent = parent.parent_path();  // "dir/"
  parent = parent.parent_path();
  std::error_code ec;
  // A file's folder must exist (AtomicFile makes none); a folder's missing parents are made.
  while (folder && !parent.empty() && !fs::exists(parent, ec) && parent != parent.root_path())
    parent = parent.parent_path();
  if (!fs::is_directory(parent, ec))
    return Status::error(what + ": " + parent.string() +
                         " is not a folder or does not exist (expected " + expected + ")");
  if (::access(parent.c_str(), W_OK | X_OK) != 0)
    return Status::error(what + ": folder " + parent.string() + " is not writable (" +
                         errno_text(errno) + "; expected " + expected + ")");
  return Status::ok();
}

std::filesystem::path temporary_sibling(const std::filesystem::path& path) {
  static std::atomic<unsigned> counter{0};
  // Appended piece by piece: GCC 12 at -O3 warns (-Wrestrict, a false positive) on the
  // chain of operator+ temporaries.
  std::string name = ".";
  name += path.filename().string();
  name += ".tmp-";
  name += std::to_string(::getpid());
  name += '-';
  name += std::to_string(counter++);
  return path.parent_path() / name;
}

Status AtomicFile::open(const std::filesystem::path& final_path) {
  abandon();
  final_ = final_path;
  temp_ = temporary_sibling(final_path);
  const int fd = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0)
    return Status::error(final_.string() + ": cannot create file (" + errno_text(errno) + ")");
  file_ = ::fdopen(fd, "wb");
  if (!file_) {
    const int err = errno;
    ::close(fd);
    ::unlink(temp_.c_str());
    return Status::error(final_.string() + ": cannot open file (" + errno_text(err) + ")");
  }
  write_errno_ = 0;
  return Status::ok();
}

bool AtomicFile::write(const void* data, std::size_t size) {
  if (!file_) return false;
  if (size && std::fwrite(data, 1, size, file_) != size) {
    if (!write_errno_) write_errno_ = errno ? errno : EIO;
    return false;
  }
  return true;
}

Status AtomicFile::commit(bool durable) {
  if (!file_) return Status::error(final_.string() + ": nothing to commit");
  int err = write_errno_;
  if (!err && std::fflush(file_) != 0) err = errno;
  if (!err && std::ferror(file_)) err = EIO;
  if (!err && durable && ::fsync(::fileno(file_)) != 0) err = errno;
  if (std::fclose(file_) != 0 && !err) err = errno;
  file_ = nullptr;
  if (!err && ::rename(temp_.c_str(), final_.c_str()) != 0) err = errno;
  if (err) {
    ::unlink(temp_.c_str());
    return Status::error(final_.string() + ": write failed (" + errno_text(err) + ")");
  }
  return Status::ok();
}

void AtomicFile::abandon() noexcept {
  if (!file_) return;
  std::fclose(file_);
  file_ = nullptr;
  ::unlink(temp_.c_str());
}

}  // namespace ardcell
