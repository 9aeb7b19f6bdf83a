// PNG output: what libpng reads back is exactly what was written; files appear atomically;
// the sequence sink names frames by step.
#include "drivers/png_writer.h"

#include <png.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace ardcell {
namespace {

namespace fs = std::filesystem;

class PngWriterTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("ardcell_png_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::size_t file_count() const {
    return std::size_t(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()));
  }
  fs::path dir_;
};

ImageRgb8 test_image(int w, int h) {
  ImageRgb8 img;
  img.resize(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      uint8_t* p = img.row(y) + 3 * x;
      p[0] = uint8_t(x * 7 + y);
      p[1] = uint8_t(y * 13);
      p[2] = uint8_t((x * y) ^ 0x5a);
    }
  return img;
}

// Reads a PNG with libpng's simplified API as 8-bit RGB.
bool read_png_rgb(const fs::path& path, ImageRgb8& out) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, path.c_str())) return false;
  image.format = PNG_FORMAT_RGB;
  out.resize(int(image.width), int(image.height));
  const bool ok = png_image_finish_read(&image, nullptr, out.rgb.data(), 0, nullptr) != 0;
  png_image_free(&image);
  return ok;
}

TEST_F(PngWriterTest, LibpngReadsBackExactlyWhatWasWritten) {
  for (auto [w, h] : {std::pair{1, 1}, {37, 21}, {256, 256}}) {
    const ImageRgb8 img = test_image(w, h);
    const fs::path path = dir_ / ("frame_" + std::to_string(w) + ".png");
    Status s = write_png(path, img);
    ASSERT_TRUE(s) << s.message();
    ImageRgb8 back;
    ASSERT_TRUE(read_png_rgb(path, back));
    EXPECT_EQ(back.width, w);
    EXPECT_EQ(back.height, h);
    EXPECT_EQ(back.rgb, img.rgb);
  }
  EXPECT_EQ(file_count(), 3u);  // no temporaries left
}

TEST_F(PngWriterTest, EveryCompressionLevelDecodesTheSame) {
  const ImageRgb8 img = test_image(64, 40);
  for (int level : {0, 1, 9}) {
    const fs::path path = dir_ / ("l" + std::to_string(level) + ".png");
    ASSERT_TRUE(write_png(path, img, level));
    ImageRgb8 back;
    ASSERT_TRUE(read_png_rgb(path, back));
    EXPECT_EQ(back.rgb, img.rgb);
  }
}

TEST_F(PngWriterTest, ReplacingAFileIsAtomicAndFailuresLeaveNothing) {
  const fs::path path = dir_ / "a.png";
  ASSERT_TRUE(write_png(path, test_image(8, 8)));
  ASSERT_TRUE(write_png(path, test_image(9, 3)));
  ImageRgb8 back;
  ASSERT_TRUE(read_png_rgb(path, back));
  EXPECT_EQ(back.width, 9);
  Status s = write_png(dir_ / "missing" / "b.png", test_image(4, 4));
  ASSERT_FALSE(s);
  EXPECT_NE(s.message().find("b.png"), std::string::npos);
  ImageRgb8 empty;
  EXPECT_FALSE(write_png(dir_ / "c.png", empty));
  EXPECT_EQ(file_count(), 1u);
}

TEST_F(PngWriterTest, SequenceSinkNamesFramesByStep) {
  PngSequenceSink sink(dir_, "dye");
  const ImageRgb8 img = test_image(5, 4);
  ASSERT_TRUE(sink.write(img, FrameInfo{0, 10, 0.1}));
  ASSERT_TRUE(sink.write(img, FrameInfo{1, 20, 0.2}));
  ASSERT_TRUE(sink.finish());
  EXPECT_TRUE(fs::exists(dir_ / "dye_00000010.png"));
  EXPECT_TRUE(fs::exists(dir_ / "dye_00000020.png"));
  EXPECT_EQ(file_count(), 2u);
  EXPECT_EQ(sink.describe(), (dir_ / "dye_*.png").string());
}

}  // namespace
}  // namespace ardcell
