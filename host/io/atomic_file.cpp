#include "host/io/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>

namespace ardcell {

std::string errno_text(int err) { return std::strerror(err); }

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
