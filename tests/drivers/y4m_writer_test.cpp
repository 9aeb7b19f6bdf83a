// Y4M output: stream and frame layout per the YUV4MPEG2 format, BT.601 limited-range colour
// conversion (reference colours and a round trip back to RGB), 4:2:0 chroma averaging, the
// file appearing only when finished; and the ffmpeg pipe with a stand-in ffmpeg on PATH.
#include "drivers/y4m_writer.h"

#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include "drivers/ffmpeg_pipe.h"

namespace ardcell {
namespace {

namespace fs = std::filesystem;

class Y4mWriterTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("ardcell_y4m_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  static std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
  }
  std::size_t file_count() const {
    return std::size_t(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()));
  }
  fs::path dir_;
};

ImageRgb8 solid(int w, int h, uint8_t r, uint8_t g, uint8_t b) {
  ImageRgb8 img;
  img.resize(w, h);
  for (int i = 0; i < w * h; ++i) {
    img.rgb[3 * i] = r;
    img.rgb[3 * i + 1] = g;
    img.rgb[3 * i + 2] = b;
  }
  return img;
}

TEST_F(Y4mWriterTest, Bt601ReferenceColours) {
  struct Ref {
    uint8_t r, g, b, y, cb, cr;
  };
  // ITU-R BT.601 limited range: black 16/128/128, white 235/128/128, and the primaries.
  const Ref refs[] = {{0, 0, 0, 16, 128, 128},   {255, 255, 255, 235, 128, 128},
                      {255, 0, 0, 81, 90, 240},  {0, 255, 0, 145, 54, 34},
                      {0, 0, 255, 41, 240, 110}, {128, 128, 128, 126, 128, 128}};
  for (const Ref& r : refs) {
    uint8_t y, cb, cr;
    rgb_to_ycbcr601(r.r, r.g, r.b, y, cb, cr);
    EXPECT_EQ(int(y), int(r.y)) << int(r.r) << "," << int(r.g) << "," << int(r.b);
    EXPECT_EQ(int(cb), int(r.cb));
    EXPECT_EQ(int(cr), int(r.cr));
  }
}

TEST_F(Y4mWriterTest, ConversionInvertsWithinQuantisation) {
  // Inverse BT.601 of every 17th RGB level recovers the colour within 2 levels.
  for (int r = 0; r < 256; r += 17)
    for (int g = 0; g < 256; g += 17)
      for (int b = 0; b < 256; b += 17) {
        uint8_t y, cb, cr;
        rgb_to_ycbcr601(uint8_t(r), uint8_t(g), uint8_t(b), y, cb, cr);
        const double Y = (y - 16) * 255.0 / 219, Cb = (cb - 128) * 255.0 / 224,
                     Cr = (cr - 128) * 255.0 / 224;
        const double R = Y + 1.402 * Cr, G = Y - 0.344136 * Cb - 0.714136 * Cr, B = Y + 1.772 * Cb;
        ASSERT_NEAR(R, r, 2.0);
        ASSERT_NEAR(G, g, 2.0);
        ASSERT_NEAR(B, b, 2.0);
      }
}

TEST_F(Y4mWriterTest, FileLayoutIsHeaderThenFramesOf420Planes) {
  const fs::path path = dir_ / "clip.y4m";
  {
    Y4mFileSink sink(path, 4, 2, 25);
    ImageRgb8 img = solid(4, 2, 255, 255, 255);
    // Left 2x2 block: two black and two white pixels; chroma stays neutral, luma per pixel.
    img.row(0)[0] = img.row(0)[1] = img.row(0)[2] = 0;
    img.row(1)[3] = img.row(1)[4] = img.row(1)[5] = 0;
    ASSERT_TRUE(sink.write(img, {}));
    ASSERT_TRUE(sink.write(solid(4, 2, 255, 0, 0), {}));
    EXPECT_FALSE(fs::exists(path));  // only a temporary until finish()
    ASSERT_TRUE(sink.finish());
  }
  const std::string data = slurp(path);
  const std::string header = "YUV4MPEG2 W4 H2 F25:1 Ip A1:1 C420jpeg\n";
  ASSERT_EQ(data.substr(0, header.size()), header);
  const std::size_t frame = 6 + 8 + 2 + 2;
  ASSERT_EQ(data.size(), header.size() + 2 * frame);
  const std::string f0 = data.substr(header.size(), frame);
  EXPECT_EQ(f0.substr(0, 6), "FRAME\n");
  const std::string luma = f0.substr(6, 8);
  EXPECT_EQ(luma, std::string(
                      {16, char(235), char(235), char(235), char(235), 16, char(235), char(235)}));
  EXPECT_EQ(uint8_t(f0[14]), 128);  // Cb of the left block
  EXPECT_EQ(uint8_t(f0[16]), 128);  // Cr of the left block
  const std::string f1 = data.substr(header.size() + frame, frame);
  EXPECT_EQ(f1.substr(0, 6), "FRAME\n");
  EXPECT_EQ(uint8_t(f1[6]), 81);
  EXPECT_EQ(uint8_t(f1[14]), 90);
  EXPECT_EQ(uint8_t(f1[16]), 240);
  EXPECT_EQ(file_count(), 1u);
}

TEST_F(Y4mWriterTest, OddSizesUse444) {
  EXPECT_EQ(y4m_chroma_for(5, 4), Y4mChroma::k444);
  EXPECT_EQ(y4m_chroma_for(4, 3), Y4mChroma::k444);
  EXPECT_EQ(y4m_chroma_for(4, 4), Y4mChroma::k420);
  const fs::path path = dir_ / "odd.y4m";
  Y4mFileSink sink(path, 3, 3, 30);
  ASSERT_TRUE(sink.write(solid(3, 3, 0, 0, 255), {}));
  ASSERT_TRUE(sink.finish());
  const std::string data = slurp(path);
  const std::string header = "YUV4MPEG2 W3 H3 F30:1 Ip A1:1 C444\n";
  ASSERT_EQ(data.substr(0, header.size()), header);
  ASSERT_EQ(data.size(), header.size() + 6 + 27);
  EXPECT_EQ(uint8_t(data[header.size() + 6 + 9]), 240);  // Cb of blue
}

TEST_F(Y4mWriterTest, AFrameOfAnotherSizeIsRefusedAndAnUnfinishedFileIsRemoved) {
  {
    Y4mFileSink sink(dir_ / "a.y4m", 4, 4, 30);
    ASSERT_TRUE(sink.write(solid(4, 4, 1, 2, 3), {}));
    EXPECT_FALSE(sink.write(solid(2, 2, 1, 2, 3), {}));
  }  // destroyed without finish()
  EXPECT_EQ(file_count(), 0u);
}

TEST_F(Y4mWriterTest, VideoSinkFallsBackToY4mWithoutFfmpeg) {
  const char* old = std::getenv("PATH");
  const std::string saved = old ? old : "";
  ::setenv("PATH", dir_.c_str(), 1);  // no ffmpeg here
  std::unique_ptr<FrameSink> sink;
  std::string note;
  Status s = make_video_sink(dir_ / "clip.mp4", 4, 4, 30, sink, note);
  ::setenv("PATH", saved.c_str(), 1);
  ASSERT_TRUE(s);
  EXPECT_NE(note.find("ffmpeg not found on PATH"), std::string::npos);
  EXPECT_NE(note.find("clip.y4m"), std::string::npos);
  ASSERT_TRUE(sink->write(solid(4, 4, 0, 0, 0), {}));
  ASSERT_TRUE(sink->finish());
  EXPECT_TRUE(fs::exists(dir_ / "clip.y4m"));
  EXPECT_FALSE(fs::exists(dir_ / "clip.mp4"));
}

TEST_F(Y4mWriterTest, VideoSinkPipesRawFramesToFfmpegOnPath) {
  // A stand-in ffmpeg: records its arguments and copies stdin to the output (its last arg).
  const fs::path bin = dir_ / "bin";
  fs::create_directories(bin);
  const fs::path fake = bin / "ffmpeg";
  std::ofstream(fake) << "#!/bin/sh\n"
                         "for a; do last=$a; done\n"
                         "echo \"$@\" > \"" +
                             (dir_ / "args.txt").string() +
                             "\"\n"
                             "/bin/cat > \"$last\"\n";
  ::chmod(fake.c_str(), 0755);
  const char* old = std::getenv("PATH");
  const std::string saved = old ? old : "";
  ::setenv("PATH", bin.c_str(), 1);
  std::unique_ptr<FrameSink> sink;
  std::string note;
  Status s = make_video_sink(dir_ / "clip.mp4", 6, 2, 24, sink, note);
  ::setenv("PATH", saved.c_str(), 1);
  ASSERT_TRUE(s) << s.message();
  EXPECT_TRUE(note.empty());
  const ImageRgb8 a = solid(6, 2, 1, 2, 3), b = solid(6, 2, 4, 5, 6);
  ASSERT_TRUE(sink->write(a, {}));
  ASSERT_TRUE(sink->write(b, {}));
  ASSERT_TRUE(sink->finish());
  EXPECT_EQ(slurp(dir_ / "clip.mp4"),
            std::string(a.rgb.begin(), a.rgb.end()) + std::string(b.rgb.begin(), b.rgb.end()));
  const std::string args = slurp(dir_ / "args.txt");
  EXPECT_NE(args.find("-f rawvideo -pixel_format rgb24 -video_size 6x2 -framerate 24 -i -"),
            std::string::npos)
      << args;
  // Nothing but the finished video, the script's folder and its record.
  EXPECT_EQ(file_count(), 3u);
}

TEST_F(Y4mWriterTest, AFailingFfmpegIsReportedAndLeavesNoVideo) {
  const fs::path bin = dir_ / "bin";
  fs::create_directories(bin);
  std::ofstream(bin / "ffmpeg") << "#!/bin/sh\n/bin/cat > /dev/null\nexit 3\n";
  ::chmod((bin / "ffmpeg").c_str(), 0755);
  auto ffmpeg = std::optional<fs::path>(bin / "ffmpeg");
  std::unique_ptr<FfmpegPipeSink> sink;
  ASSERT_TRUE(FfmpegPipeSink::start(*ffmpeg, dir_ / "x.mp4", 2, 2, 30, sink));
  ASSERT_TRUE(sink->write(solid(2, 2, 9, 9, 9), {}));
  Status s = sink->finish();
  ASSERT_FALSE(s);
  EXPECT_NE(s.message().find("exit status 3"), std::string::npos) << s.message();
  EXPECT_EQ(file_count(), 1u);  // bin/
}

}  // namespace
}  // namespace ardcell
