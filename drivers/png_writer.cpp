#include "drivers/png_writer.h"

#include <png.h>

#include <csetjmp>
#include <cstdio>
#include <vector>

#include "host/io/atomic_file.h"

namespace ardcell {
namespace {

struct PngErrorText {
  char text[200] = "libpng error";
};

void on_png_error(png_structp png, png_const_charp message) {
  auto* err = static_cast<PngErrorText*>(png_get_error_ptr(png));
  if (err) std::snprintf(err->text, sizeof err->text, "%s", message);
  png_longjmp(png, 1);
}

void on_png_warning(png_structp, png_const_charp) {}

// What encode_png writes: `row` gives row y of `image` as PNG bytes (8-bit rows point into the
// image itself; 16-bit rows are packed big-endian into `scratch`, as PNG stores them, whatever
// the host's byte order).
struct PngRows {
  int width = 0, height = 0, bit_depth = 8, color_type = PNG_COLOR_TYPE_RGB;
  const uint8_t* (*row)(const void* image, int y, uint8_t* scratch) = nullptr;
  const void* image = nullptr;
  uint8_t* scratch = nullptr;
};

// Writes the PNG stream to an open file; false with err.text on failure. Kept free of C++
// objects with destructors because libpng reports errors by longjmp.
bool encode_png(std::FILE* file, const PngRows& rows, int level, PngErrorText& err) {
  png_structp png =
      png_create_write_struct(PNG_LIBPNG_VER_STRING, &err, on_png_error, on_png_warning);
  if (!png) return false;
  png_infop info = png_create_info_struct(png);
  if (!info) {
    png_destroy_write_struct(&png, nullptr);
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_init_io(png, file);
  png_set_compression_level(png, level);
  png_set_IHDR(png, info, png_uint_32(rows.width), png_uint_32(rows.height), rows.bit_depth,
               rows.color_type, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (int y = 0; y < rows.height; ++y) png_write_row(png, rows.row(rows.image, y, rows.scratch));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

// Encodes into a temporary file renamed into place (AtomicFile): never a half-written PNG.
Status write_png_rows(const std::filesystem::path& path, const PngRows& rows, int level) {
  AtomicFile file;
  if (Status s = file.open(path); !s) return s;
  PngErrorText err;
  if (!encode_png(file.file(), rows, level, err)) {
    file.abandon();
    return Status::error(path.string() + ": PNG encoding failed (" + err.text + ")");
  }
  return file.commit();
}

const uint8_t* rgb8_row(const void* image, int y, uint8_t*) {
  return static_cast<const ImageRgb8*>(image)->row(y);
}

const uint8_t* gray8_row(const void* image, int y, uint8_t*) {
  const auto* im = static_cast<const ImageGray8*>(image);
  return im->pixels.data() + std::size_t(y) * std::size_t(im->width);
}

const uint8_t* gray16_row(const void* image, int y, uint8_t* scratch) {
  const auto* im = static_cast<const ImageGray16*>(image);
  const uint16_t* src = im->pixels.data() + std::size_t(y) * std::size_t(im->width);
  for (int x = 0; x < im->width; ++x) {
    scratch[2 * x] = uint8_t(src[x] >> 8);
    scratch[2 * x + 1] = uint8_t(src[x] & 0xff);
  }
  return scratch;
}

template <class Image>
bool consistent(const Image& image, std::size_t size) {
  return !image.empty() && size == std::size_t(image.width) * std::size_t(image.height);
}

}  // namespace

Status write_png(const std::filesystem::path& path, const ImageRgb8& image, int compression_level) {
  if (image.empty() || image.rgb.size() != std::size_t(image.width) * image.height * 3)
    return Status::error(path.string() + ": empty or inconsistent image");
  PngRows rows{image.width, image.height, 8, PNG_COLOR_TYPE_RGB, &rgb8_row, &image, nullptr};
  return write_png_rows(path, rows, compression_level);
}

Status write_png_gray8(const std::filesystem::path& path, const ImageGray8& image,
                       int compression_level) {
  if (!consistent(image, image.pixels.size()))
    return Status::error(path.string() + ": empty or inconsistent image");
  PngRows rows{image.width, image.height, 8, PNG_COLOR_TYPE_GRAY, &gray8_row, &image, nullptr};
  return write_png_rows(path, rows, compression_level);
}

Status write_png_gray16(const std::filesystem::path& path, const ImageGray16& image,
                        int compression_level) {
  if (!consistent(image, image.pixels.size()))
    return Status::error(path.string() + ": empty or inconsistent image");
  std::vector<uint8_t> scratch(std::size_t(image.width) * 2);
  PngRows rows{image.width, image.height,  16, PNG_COLOR_TYPE_GRAY, &gray16_row,
               &image,      scratch.data()};
  return write_png_rows(path, rows, compression_level);
}

std::filesystem::path PngSequenceSink::path_for(int64_t step) const {
  char name[64];
  std::snprintf(name, sizeof name, "_%08lld.png", static_cast<long long>(step));
  return dir_ / (prefix_ + name);
}

Status PngSequenceSink::write(const ImageRgb8& image, const FrameInfo& info) {
  return write_png(path_for(info.step), image);
}

std::string PngSequenceSink::describe() const { return (dir_ / (prefix_ + "_*.png")).string(); }

}  // namespace ardcell
