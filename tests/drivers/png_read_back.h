#pragma once
// Reads a PNG back for the CLI tests (libpng, no transformations): its header and its rows as
// stored, so 16-bit samples come big-endian, as the format keeps them.
#include <png.h>

#include <csetjmp>
#include <cstdio>
#include <filesystem>
#include <vector>

namespace ardcell {

struct PngInfo {
  bool ok = false;
  int width = 0, height = 0, bit_depth = 0, color_type = -1;
  std::vector<std::vector<uint8_t>> rows;  // as stored: 16-bit samples big-endian
};

// A tiny libpng reader: the header and the raw rows, no transformations. Only plain locals
// live across setjmp; the rows are filled through the caller's `info`.
inline bool decode_png(std::FILE* f, PngInfo& info) {
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop pi = png ? png_create_info_struct(png) : nullptr;
  if (!pi) {
    png_destroy_read_struct(&png, nullptr, nullptr);
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &pi, nullptr);
    return false;
  }
  png_init_io(png, f);
  png_read_info(png, pi);
  info.width = int(png_get_image_width(png, pi));
  info.height = int(png_get_image_height(png, pi));
  info.bit_depth = png_get_bit_depth(png, pi);
  info.color_type = png_get_color_type(png, pi);
  info.rows.assign(std::size_t(info.height), std::vector<uint8_t>(png_get_rowbytes(png, pi)));
  for (auto& row : info.rows) png_read_row(png, row.data(), nullptr);
  png_read_end(png, nullptr);
  png_destroy_read_struct(&png, &pi, nullptr);
  return true;
}

inline PngInfo read_png(const std::filesystem::path& path) {
  PngInfo info;
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return info;
  info.ok = decode_png(f, info);
  std::fclose(f);
  return info;
}

}  // namespace ardcell
