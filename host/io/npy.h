#pragma once
// NumPy .npy files (format version 1.0) holding one float32 2D array: dtype '<f4', C order,
// shape (ny, nx), row y of the array = cell row y of the grid. This is how saved states store
// fields, so that `numpy.load("u.npy")` reads them directly. Reading is strict: anything other
// than a little-endian float32 C-order 2D array of exactly the stated size is refused.
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "host/config/status.h"
#include "runtime/field.h"

namespace ardcell {

struct NpyArray {
  int ny = 0, nx = 0;
  std::vector<float> data;  // ny * nx values, row-major
  float at(int x, int y) const { return data[std::size_t(y) * nx + x]; }
};

// The largest side accepted on read (a guard against absurd headers, not a format limit).
inline constexpr int64_t kNpyMaxSide = 1 << 20;
inline constexpr int64_t kNpyMaxElements = int64_t(1) << 31;
inline constexpr std::size_t kNpyMaxHeaderBytes = 1 << 16;

// The complete header (magic, version, length, dict, padding, '\n'); its size is a multiple
// of 64 bytes, so the data that follows is aligned.
std::string npy_header(int ny, int nx);

// Writes the cells of `cells` (a box of a field, any position) as a (height, width) array.
// Written to a temporary name in the same folder and renamed: never a half-written file.
Status write_npy(const std::filesystem::path& path, View<const float> cells);

// Parses a whole .npy file held in memory. `what` names it in error messages.
Status parse_npy(std::span<const uint8_t> bytes, const std::string& what, NpyArray& out);

// Reads and parses path.
Status read_npy(const std::filesystem::path& path, NpyArray& out,
                const Int2* expected_shape = nullptr);

// Reads path and copies it into the interior of `field`, whose size must match the array.
Status read_npy_into(const std::filesystem::path& path, FieldF& field);

}  // namespace ardcell
