#pragma once
// Status: success, or one line that says what was wrong and what was expected. Bad input (CLI
// arguments, files, saved states) is reported through it, never by a crash.
#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <utility>

namespace ardcell {

class [[nodiscard]] Status {
 public:
  static Status ok() { return Status(); }
  static Status error(std::string message) { return Status(std::move(message)); }

  bool is_ok() const { return message_.empty(); }
  explicit operator bool() const { return is_ok(); }
  // The one-line description of the failure; empty on success.
  const std::string& message() const { return message_; }

 private:
  Status() = default;
  explicit Status(std::string m)
      : message_(m.empty() ? std::string("unknown error") : std::move(m)) {}
  std::string message_;
};

// Text from outside (a sender's OSC arguments, a name read from a file) as a message may show
// it: at most `max_chars` characters, then "..."; bytes outside printable ASCII and '\\' as
// \xNN, so it can never break the one line it is part of or write control codes to a terminal.
std::string escaped_prefix(std::string_view text, std::size_t max_chars);
// The same into `out` without allocating (a frame of `ardcell live` logs through it): cut short
// at a whole character where `out` is too small; NUL-terminated; returns the length written.
std::size_t escaped_prefix(std::string_view text, std::size_t max_chars, std::span<char> out);

}  // namespace ardcell
