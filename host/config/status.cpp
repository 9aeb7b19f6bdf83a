#include "host/config/status.h"

#include <algorithm>
#include <cstdio>

namespace ardcell {

std::size_t escaped_prefix(std::string_view text, std::size_t max_chars, std::span<char> out) {
  if (out.empty()) return 0;
  std::size_t n = 0;
  auto put = [&](const char* piece, std::size_t size) {
    if (n + size >= out.size()) return false;  // keeps room for the NUL
    for (std::size_t k = 0; k < size; ++k) out[n++] = piece[k];
    return true;
  };
  bool whole = true;
  for (std::size_t i = 0; i < text.size() && i < max_chars && whole; ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c >= 0x20 && c < 0x7f && c != '\\') {
      const char plain = char(c);
      whole = put(&plain, 1);
    } else {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", c);
      whole = put(hex, 4);
    }
  }
  if (whole && text.size() > max_chars) put("...", 3);
  out[n] = '\0';
  return n;
}

std::string escaped_prefix(std::string_view text, std::size_t max_chars) {
  std::string out(std::min(text.size(), max_chars) * 4 + 4, '\0');
  out.resize(escaped_prefix(text, max_chars, out));
  return out;
}

}  // namespace ardcell
