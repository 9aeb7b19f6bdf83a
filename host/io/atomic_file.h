#pragma once
// AtomicFile: writes a file under a temporary name in the destination folder and renames it
// into place on commit(), so readers see either the old file or the complete new one, never a
// half-written one. Destroying it uncommitted removes the temporary file.
#include <cstdio>
#include <filesystem>
#include <string>

#include "host/config/status.h"

namespace ardcell {

class AtomicFile {
 public:
  AtomicFile() = default;
  ~AtomicFile() { abandon(); }
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  // Creates the temporary file next to final_path (".<name>.tmp-<pid>-<n>").
  Status open(const std::filesystem::path& final_path);
  std::FILE* file() const { return file_; }
  bool is_open() const { return file_ != nullptr; }
  // Writes all of [data, data + size); false (and the error remembered) on failure.
  bool write(const void* data, std::size_t size);
  // Flushes, optionally fsyncs (durable), closes and renames into place.
  Status commit(bool durable = false);
  // Closes and removes the temporary file; a no-op when nothing is open.
  void abandon() noexcept;

  const std::filesystem::path& final_path() const { return final_; }
  const std::filesystem::path& temp_path() const { return temp_; }

 private:
  std::filesystem::path final_, temp_;
  std::FILE* file_ = nullptr;
  int write_errno_ = 0;
};

// Checks, before anything is written, that `path` can be created or replaced by AtomicFile
// (folder: false) or made as a folder of outputs (folder: true): not empty, not a folder where
// a file is expected (nor a device or FIFO), and the folder that will hold it (for a file: its
// existing parent; for a folder still to be made: its nearest existing ancestor) writable. One line
// naming the path and what was expected.
Status check_output_path(const std::filesystem::path& path, bool folder);

// A name in `dir` for a temporary sibling of `name`, unique within this process.
std::filesystem::path temporary_sibling(const std::filesystem::path& path);

// strerror(errno) for messages, e.g. "Permission denied".
std::string errno_text(int err);

}  // namespace ardcell
