// Benchmark charts (drivers/bar_chart.h, PLplot): a two-panel chart comes back from libpng at
// the asked size with its bars in the series colours, the reference marks and text in ink on a
// white page; SVG is written too; other formats and sizes are refused with one line. Through
// the binary, `ardcell bench table1` writes table1.png beside table1.md and table1.csv.
#include "drivers/bar_chart.h"

#include <png.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "tests/drivers/binary_run_fixture.h"

namespace ardcell {
namespace {

namespace fs = std::filesystem;

BarChart sample_chart() {
  BarChart c;
  c.title = "Table 1: frames per second";
  c.x_label = "grid N";
  c.y_label = "frames per second (log)";
  c.reference_label = "Cell (paper)";
  c.groups = {"128", "256", "512"};
  for (const char* name : {"fluid", "fluid + RD"}) {
    BarPanel p;
    p.title = name;
    p.series = {{"stream", {700, 220, 60}}, {"blocked", {1000, 330, NAN}}};
    p.reference = {223, 78.7, 21.4};
    c.panels.push_back(p);
  }
  return c;
}

struct Rgba {
  std::vector<uint8_t> px;
  int w = 0, h = 0;
  int count(uint8_t r, uint8_t g, uint8_t b) const {
    int n = 0;
    for (std::size_t i = 0; i + 3 < px.size(); i += 4)
      n += px[i] == r && px[i + 1] == g && px[i + 2] == b;
    return n;
  }
};

Rgba read_png_rgba(const fs::path& p) {
  png_image img{};
  img.version = PNG_IMAGE_VERSION;
  Rgba out;
  if (!png_image_begin_read_from_file(&img, p.c_str())) return out;
  img.format = PNG_FORMAT_RGBA;
  out.px.resize(PNG_IMAGE_SIZE(img));
  if (!png_image_finish_read(&img, nullptr, out.px.data(), 0, nullptr)) return {};
  out.w = int(img.width);
  out.h = int(img.height);
  return out;
}

class BarChartTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!charts_available()) GTEST_SKIP() << "built without PLplot";
    dir_ = fs::temp_directory_path() / ("ardcell_chart_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    if (!dir_.empty()) fs::remove_all(dir_, ec);
  }
  fs::path dir_;
};

TEST_F(BarChartTest, PngHasBarsMarksAndTextOnWhite) {
  const fs::path png = dir_ / "chart.png";
  const Status st = write_bar_chart(png, sample_chart(), 640, 360);
  ASSERT_TRUE(st) << st.message();
  const Rgba img = read_png_rgba(png);
  ASSERT_EQ(img.w, 640);
  ASSERT_EQ(img.h, 360);
  const int total = img.w * img.h;
  EXPECT_GT(img.count(255, 255, 255), total / 2) << "a white page";
  EXPECT_GT(img.count(40, 110, 190), 500) << "the first series' bars";
  EXPECT_GT(img.count(40, 150, 60), 500) << "the second series' bars";
  EXPECT_GT(img.count(30, 30, 30), 500) << "axes, text and reference marks";
  // Only the chart is left in the folder (no temporary file).
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);
}

TEST_F(BarChartTest, SvgIsWrittenWithItsText) {
  const fs::path svg = dir_ / "chart.svg";
  const Status st = write_bar_chart(svg, sample_chart());
  ASSERT_TRUE(st) << st.message();
  std::ifstream in(svg);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("<svg"), std::string::npos);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);
}

TEST_F(BarChartTest, BadFormatOrSizeIsOneLine) {
  Status st = write_bar_chart(dir_ / "chart.bmp", sample_chart());
  ASSERT_FALSE(st);
  EXPECT_NE(st.message().find("expected .png or .svg"), std::string::npos) << st.message();
  st = write_bar_chart(dir_ / "chart.png", sample_chart(), 10, 10);
  ASSERT_FALSE(st);
  EXPECT_NE(st.message().find("expected 200..8192"), std::string::npos) << st.message();
  EXPECT_FALSE(fs::exists(dir_ / "chart.png"));
}

using BenchTable1CliTest = BinaryRunTest;

TEST_F(BenchTable1CliTest, TinyRunWritesTableCsvAndChart) {
  if (!fs::exists(fs::path(ARDCELL_BINARY).parent_path() / "table1_bench"))
    GTEST_SKIP() << "table1_bench not built (ARDCELL_BUILD_BENCH=OFF)";
  const BinaryRunResult r =
      run("bench table1 --sizes 16 --schedules stream --min-time 0.01 --out res");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("| 16 | stream |"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(work() / "res" / "table1.md"));
  EXPECT_TRUE(fs::exists(work() / "res" / "table1.csv"));
  if (charts_available()) {
    const Rgba img = read_png_rgba(work() / "res" / "table1.png");
    EXPECT_GT(img.w, 0) << r.err;
    EXPECT_GT(img.count(40, 110, 190), 100) << "the stream bars";
  } else {
    EXPECT_NE(r.err.find("built without PLplot"), std::string::npos) << r.err;
  }
}

}  // namespace
}  // namespace ardcell
