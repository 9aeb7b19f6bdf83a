#include "host/io/user_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>

#include "host/io/atomic_file.h"

namespace ardcell {
namespace {

const char* kind_of(mode_t mode) {
  if (S_ISDIR(mode)) return "a folder";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

std::string too_large(const std::string& what, std::uint64_t cap, const std::string& expected) {
  return what + ": too large (expected " + expected + " of at most " + std::to_string(cap) +
         " bytes)";
}

}  // namespace

UserFile::~UserFile() {
  if (fd_ >= 0) ::close(fd_);
}

Status UserFile::open(const std::filesystem::path& path, std::uint64_t max_bytes,
                      std::string_view expected) {
  what_ = path.string();
  expected_ = std::string(expected);
  cap_ = max_bytes;
  if (what_.empty()) return Status::error("empty file name (expected " + expected_ + ")");
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    return Status::error(
        what_ + ": " +
        (errno == ENOENT ? std::string("not found") : "cannot read (" + errno_text(errno) + ")") +
        " (expected " + expected_ + ")");
  if (!S_ISREG(st.st_mode))
    return Status::error(what_ + ": is " + kind_of(st.st_mode) + " (expected " + expected_ + ")");
  if (std::uint64_t(st.st_size) > cap_) return Status::error(too_large(what_, cap_, expected_));
  // O_NONBLOCK: should the path have been swapped for a FIFO since stat, open must not hang.
  fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOCTTY | O_NONBLOCK);
  if (fd_ < 0)
    return Status::error(what_ + ": cannot open (" + errno_text(errno) + "; expected " + expected_ +
                         ")");
  if (::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode))
    return Status::error(what_ + ": is " + kind_of(st.st_mode) + " (expected " + expected_ + ")");
  if (std::uint64_t(st.st_size) > cap_) return Status::error(too_large(what_, cap_, expected_));
  ::fcntl(fd_, F_SETFL, ::fcntl(fd_, F_GETFL) & ~O_NONBLOCK);
  size_ = std::uint64_t(st.st_size);
  return Status::ok();
}

Status UserFile::read(void* dst, std::size_t n) {
  if (fd_ < 0) return Status::error(what_ + ": not open (expected " + expected_ + ")");
  if (read_ + n > cap_) return Status::error(too_large(what_, cap_, expected_));
  auto* p = static_cast<char*>(dst);
  std::size_t done = 0;
  while (done < n) {
    const ssize_t got = ::read(fd_, p + done, n - done);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0)
      return Status::error(what_ + ": read failed (" + errno_text(errno) + "; expected " +
                           expected_ + ")");
    if (got == 0) return Status::error(what_ + ": truncated (expected " + expected_ + ")");
    done += std::size_t(got);
  }
  read_ += n;
  return Status::ok();
}

Status UserFile::read_rest(std::string& out) {
  out.clear();
  if (fd_ < 0) return Status::error(what_ + ": not open (expected " + expected_ + ")");
  // The size stat gave, but never trusted: /proc files say 0, others grow.
  out.reserve(std::size_t(std::min(size_, cap_)));
  char buf[1 << 16];
  while (true) {
    const ssize_t got = ::read(fd_, buf, sizeof buf);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0)
      return Status::error(what_ + ": read failed (" + errno_text(errno) + "; expected " +
                           expected_ + ")");
    if (got == 0) break;
    if (read_ + std::uint64_t(got) > cap_) return Status::error(too_large(what_, cap_, expected_));
    out.append(buf, std::size_t(got));
    read_ += std::uint64_t(got);
  }
  return Status::ok();
}

Status read_user_file(const std::filesystem::path& path, std::uint64_t max_bytes,
                      std::string_view expected, std::string& out) {
  UserFile file;
  if (Status s = file.open(path, max_bytes, expected); !s) return s;
  return file.read_rest(out);
}

}  // namespace ardcell
