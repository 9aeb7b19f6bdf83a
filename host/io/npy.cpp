#include "host/io/npy.h"

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cstring>
#include <fstream>

#include "host/io/atomic_file.h"
#include "host/io/user_file.h"

namespace ardcell {
namespace {

constexpr char kMagic[] = "\x93NUMPY";
constexpr std::size_t kMagicSize = 6;

// A cursor over the header dictionary, e.g. "{'descr': '<f4', 'fortran_order': False,
// 'shape': (3, 4), }". Only the literals the format uses are understood.
class DictParser {
 public:
  explicit DictParser(std::string_view s) : s_(s) {}
  void skip_space() {
    while (i_ < s_.size() && (s_[i_] == ' ' || s_[i_] == '\t')) ++i_;
  }
  bool eat(char c) {
    skip_space();
    if (i_ < s_.size() && s_[i_] == c) {
      ++i_;
      return true;
    }
    return false;
  }
  bool peek(char c) {
    skip_space();
    return i_ < s_.size() && s_[i_] == c;
  }
  bool string_literal(std::string& out) {
    skip_space();
    if (i_ >= s_.size() || (s_[i_] != '\'' && s_[i_] != '"')) return false;
    const char quote = s_[i_++];
    const std::size_t end = s_.find(quote, i_);
    if (end == std::string_view::npos) return false;
    out.assign(s_.substr(i_, end - i_));
    i_ = end + 1;
    return true;
  }
  bool word(std::string_view w) {
    skip_space();
    if (s_.substr(i_, w.size()) != w) return false;
    i_ += w.size();
    return true;
  }
  bool integer(int64_t& out) {
    skip_space();
    std::size_t j = i_;
    int64_t v = 0;
    while (j < s_.size() && s_[j] >= '0' && s_[j] <= '9') {
      if (v > (int64_t(1) << 40)) return false;
      v = v * 10 + (s_[j] - '0');
      ++j;
    }
    if (j == i_) return false;
    // Python 2 era writers append 'L' to longs.
    if (j < s_.size() && s_[j] == 'L') ++j;
    i_ = j;
    out = v;
    return true;
  }
  bool at_end() {
    skip_space();
    return i_ == s_.size();
  }

 private:
  std::string_view s_;
  std::size_t i_ = 0;
};

Status parse_header(std::string_view dict, const std::string& what, int64_t& ny, int64_t& nx) {
  auto bad = [&](const std::string& why) {
    return Status::error(what + ": bad .npy header: " + why +
                         " (expected {'descr': '<f4', 'fortran_order': False, 'shape': (ny, nx)})");
  };
  DictParser p(dict);
  if (!p.eat('{')) return bad("no dictionary");
  bool have_descr = false, have_order = false, have_shape = false;
  std::vector<int64_t> shape;
  while (!p.eat('}')) {
    std::string key;
    if (!p.string_literal(key)) return bad("expected a quoted key");
    if (!p.eat(':')) return bad("expected ':' after '" + key + "'");
    if (key == "descr") {
      std::string descr;
      if (!p.string_literal(descr)) return bad("descr is not a string");
      if (descr != "<f4")
        return Status::error(what + ": dtype '" + descr +
                             "' is not supported (expected little-endian float32 '<f4')");
      have_descr = true;
    } else if (key == "fortran_order") {
      if (p.word("True"))
        return Status::error(what + ": Fortran order is not supported (expected C order)");
      if (!p.word("False")) return bad("fortran_order is not True or False");
      have_order = true;
    } else if (key == "shape") {
      if (!p.eat('(')) return bad("shape is not a tuple");
      while (!p.eat(')')) {
        int64_t n = 0;
        if (!p.integer(n)) return bad("shape holds a non-integer");
        shape.push_back(n);
        if (shape.size() > 8) return bad("shape has too many dimensions");
        if (!p.eat(',') && !p.peek(')')) return bad("expected ',' or ')' in shape");
      }
      have_shape = true;
    } else {
      return bad("unexpected key '" + key + "'");
    }
    if (!p.eat(',') && !p.peek('}')) return bad("expected ',' or '}'");
  }
  if (!p.at_end()) return bad("text after the dictionary");
  if (!have_descr || !have_order || !have_shape) return bad("missing key");
  if (shape.size() != 2)
    return Status::error(what + ": array has " + std::to_string(shape.size()) +
                         " dimensions (expected 2: ny, nx)");
  for (int64_t n : shape)
    if (n < 1 || n > kNpyMaxSide)
      return Status::error(what + ": shape (" + std::to_string(shape[0]) + ", " +
                           std::to_string(shape[1]) + ") out of range (expected 1.." +
                           std::to_string(kNpyMaxSide) + " per side)");
  if (shape[0] * shape[1] > kNpyMaxElements) return Status::error(what + ": array too large");
  ny = shape[0];
  nx = shape[1];
  return Status::ok();
}

}  // namespace

std::string npy_header(int ny, int nx) {
  std::string dict = "{'descr': '<f4', 'fortran_order': False, 'shape': (" + std::to_string(ny) +
                     ", " + std::to_string(nx) + "), }";
  // magic (6) + version (2) + length (2) + dict + padding + '\n' = multiple of 64.
  const std::size_t unpadded = kMagicSize + 2 + 2 + dict.size() + 1;
  dict.append((64 - unpadded % 64) % 64, ' ');
  dict.push_back('\n');
  std::string header(kMagic, kMagicSize);
  header.push_back('\x01');
  header.push_back('\x00');
  header.push_back(static_cast<char>(dict.size() & 0xff));
  header.push_back(static_cast<char>((dict.size() >> 8) & 0xff));
  return header + dict;
}

Status write_npy(const std::filesystem::path& path, View<const float> cells) {
  const Box2 box = cells.box();
  static_assert(std::endian::native == std::endian::little, "npy writer assumes little-endian");
  AtomicFile file;
  if (Status s = file.open(path); !s) return s;
  const std::string header = npy_header(box.height(), box.width());
  file.write(header.data(), header.size());
  for (int y = box.min.y; y < box.max.y; ++y)
    file.write(cells.row(y) + box.min.x, std::size_t(box.width()) * sizeof(float));
  return file.commit(true);
}

namespace {

// The header at the start of `bytes` (which may hold only part of the payload): shape and the
// offset of the data.
Status parse_npy_header(std::span<const uint8_t> bytes, const std::string& what, int64_t& ny,
                        int64_t& nx, std::size_t& data_offset) {
  if (bytes.size() < kMagicSize + 4 || std::memcmp(bytes.data(), kMagic, kMagicSize) != 0)
    return Status::error(what + ": not a NumPy .npy file (expected the magic \\x93NUMPY)");
  const uint8_t major = bytes[6], minor = bytes[7];
  std::size_t header_len = 0, prefix = 0;
  if (major == 1 && minor == 0) {
    header_len = std::size_t(bytes[8]) | std::size_t(bytes[9]) << 8;
    prefix = 10;
  } else if (major == 2 && minor == 0) {
    if (bytes.size() < 12) return Status::error(what + ": truncated .npy header");
    header_len = std::size_t(bytes[8]) | std::size_t(bytes[9]) << 8 | std::size_t(bytes[10]) << 16 |
                 std::size_t(bytes[11]) << 24;
    prefix = 12;
  } else {
    return Status::error(what + ": .npy format version " + std::to_string(major) + "." +
                         std::to_string(minor) + " is not supported (expected 1.0 or 2.0)");
  }
  if (header_len > kNpyMaxHeaderBytes)
    return Status::error(what + ": .npy header of " + std::to_string(header_len) +
                         " bytes (expected at most " + std::to_string(kNpyMaxHeaderBytes) + ")");
  if (header_len > bytes.size() - prefix) return Status::error(what + ": truncated .npy header");
  std::string_view dict(reinterpret_cast<const char*>(bytes.data()) + prefix, header_len);
  if (dict.empty() || dict.back() != '\n')
    return Status::error(what + ": bad .npy header (expected it to end with a newline)");
  dict.remove_suffix(1);
  while (!dict.empty() && dict.back() == ' ') dict.remove_suffix(1);
  if (Status s = parse_header(dict, what, ny, nx); !s) return s;
  data_offset = prefix + header_len;
  return Status::ok();
}

Status check_data_size(const std::string& what, std::uint64_t have, int64_t ny, int64_t nx) {
  const std::uint64_t data_bytes = std::uint64_t(ny * nx) * sizeof(float);
  if (have == data_bytes) return Status::ok();
  return Status::error(what + ": holds " + std::to_string(have) + " data bytes (expected " +
                       std::to_string(data_bytes) + " for shape (" + std::to_string(ny) + ", " +
                       std::to_string(nx) + ") float32)");
}

}  // namespace

Status parse_npy(std::span<const uint8_t> bytes, const std::string& what, NpyArray& out) {
  int64_t ny = 0, nx = 0;
  std::size_t offset = 0;
  if (Status s = parse_npy_header(bytes, what, ny, nx, offset); !s) return s;
  if (Status s = check_data_size(what, bytes.size() - offset, ny, nx); !s) return s;
  out.ny = int(ny);
  out.nx = int(nx);
  out.data.resize(std::size_t(ny * nx));
  std::memcpy(out.data.data(), bytes.data() + offset, std::size_t(ny * nx) * sizeof(float));
  return Status::ok();
}

Status read_npy(const std::filesystem::path& path, NpyArray& out, const Int2* expected_shape) {
  const std::string what = path.string();
  UserFile file;
  if (Status s =
          file.open(path, std::uint64_t(kNpyMaxElements) * sizeof(float) + kNpyMaxHeaderBytes + 12,
                    "a float32 .npy file");
      !s)
    return s;
  // The header first: its shape is checked against the file size (and the grid) before any
  // of the payload is read.
  std::vector<uint8_t> head(
      std::size_t(std::min<std::uint64_t>(file.size(), 12 + kNpyMaxHeaderBytes)));
  if (Status s = file.read(head.data(), head.size()); !s) return s;
  int64_t ny = 0, nx = 0;
  std::size_t offset = 0;
  if (Status s = parse_npy_header(head, what, ny, nx, offset); !s) return s;
  if (expected_shape && (ny != expected_shape->y || nx != expected_shape->x))
    return Status::error(what + ": shape (" + std::to_string(ny) + ", " + std::to_string(nx) +
                         ") does not match the grid (expected (" +
                         std::to_string(expected_shape->y) + ", " +
                         std::to_string(expected_shape->x) + "))");
  if (Status s = check_data_size(what, file.size() - offset, ny, nx); !s) return s;
  out.ny = int(ny);
  out.nx = int(nx);
  out.data.resize(std::size_t(ny * nx));
  const std::size_t in_head = head.size() - offset;
  std::memcpy(out.data.data(), head.data() + offset, in_head);
  return file.read(reinterpret_cast<uint8_t*>(out.data.data()) + in_head,
                   out.data.size() * sizeof(float) - in_head);
}

Status read_npy_into(const std::filesystem::path& path, FieldF& field) {
  NpyArray array;
  const Int2 shape{field.nx(), field.ny()};
  if (Status s = read_npy(path, array, &shape); !s) return s;
  for (int y = 0; y < array.ny; ++y)
    std::memcpy(field.row(y), array.data.data() + std::size_t(y) * array.nx,
                std::size_t(array.nx) * sizeof(float));
  return Status::ok();
}

}  // namespace ardcell
