#include "drivers/png_writer.h"

#include <png.h>

#include <csetjmp>
#include <cstdio>

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

// Writes the PNG stream to an open file; false with err.text on failure. Kept free of C++
// objects with destructors because libpng reports errors by longjmp.
bool encode_png(std::FILE* file, const ImageRgb8& image, int level, PngErrorText& err) {
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
  png_set_IHDR(png, info, png_uint_32(image.width), png_uint_32(image.height), 8,
               PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (int y = 0; y < image.height; ++y) png_write_row(png, image.row(y));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

}  // namespace

Status write_png(const std::filesystem::path& path, const ImageRgb8& image, int compression_level) {
  if (image.empty() || image.rgb.size() != std::size_t(image.width) * image.height * 3)
    return Status::error(path.string() + ": empty or inconsistent image");
  AtomicFile file;
  if (Status s = file.open(path); !s) return s;
  PngErrorText err;
  if (!encode_png(file.file(), image, compression_level, err)) {
    file.abandon();
    return Status::error(path.string() + ": PNG encoding failed (" + err.text + ")");
  }
  return file.commit();
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
