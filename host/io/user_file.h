#pragma once
// Reading a file a user names (presets, saved states, .npy fields, stroke recordings, HID
// recordings, configs): the one way to open one. Before anything is read the path must be a
// regular file (FIFOs, devices, sockets and folders are refused without opening them) no larger
// than the caller's cap; reads never go past the cap, even when the file grows meanwhile or
// reports no size (/proc). Every failure is one line naming the file and what was expected.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "host/config/status.h"

namespace ardcell {

// Caps for the kinds of files read (bytes).
inline constexpr std::uint64_t kMaxTextConfigBytes = std::uint64_t(1) << 20;   // presets, meta.json
inline constexpr std::uint64_t kMaxRecordingBytes = std::uint64_t(256) << 20;  // strokes, HID

class UserFile {
 public:
  UserFile() = default;
  ~UserFile();
  UserFile(const UserFile&) = delete;
  UserFile& operator=(const UserFile&) = delete;

  // Checks the type and size of `path` and opens it. `expected` says what the file should be
  // ("a preset TOML file"); it ends every message.
  Status open(const std::filesystem::path& path, std::uint64_t max_bytes,
              std::string_view expected);
  std::uint64_t size() const { return size_; }
  // Reads exactly `n` bytes at the current position ("truncated" when the file ends first).
  Status read(void* dst, std::size_t n);
  // Reads what is left, at most the cap, into `out` (an error when more is there).
  Status read_rest(std::string& out);

 private:
  std::string what_, expected_;
  std::uint64_t cap_ = 0, size_ = 0, read_ = 0;
  int fd_ = -1;
};

// UserFile::open + read_rest: the whole file as text or bytes.
Status read_user_file(const std::filesystem::path& path, std::uint64_t max_bytes,
                      std::string_view expected, std::string& out);

}  // namespace ardcell
