// Charts (drivers/chart.h, PLplot): a two-panel bar chart comes back from libpng at
// the asked size with its bars in the series colours, the reference marks and text in ink on a
// white page; SVG is written too; a polar chart draws each sign in its colour; other formats
// and sizes are refused with one line. Through the binary, `ardcell bench table1` writes
// table1.png beside table1.md and table1.csv.
#include "drivers/chart.h"

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

class ChartTest : public ::testing::Test {
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

TEST_F(ChartTest, PngHasBarsMarksAndTextOnWhite) {
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

TEST_F(ChartTest, SvgIsWrittenWithItsText) {
  const fs::path svg = dir_ / "chart.svg";
  const Status st = write_bar_chart(svg, sample_chart());
  ASSERT_TRUE(st) << st.message();
  std::ifstream in(svg);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("<svg"), std::string::npos);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);
}

TEST_F(ChartTest, BadFormatOrSizeIsOneLine) {
  Status st = write_bar_chart(dir_ / "chart.bmp", sample_chart());
  ASSERT_FALSE(st);
  EXPECT_NE(st.message().find("expected .png or .svg"), std::string::npos) << st.message();
  st = write_bar_chart(dir_ / "chart.png", sample_chart(), 10, 10);
  ASSERT_FALSE(st);
  EXPECT_NE(st.message().find("expected 200..8192"), std::string::npos) << st.message();
  EXPECT_FALSE(fs::exists(dir_ / "chart.png"));
}

TEST_F(ChartTest, PolarChartDrawsEachSignInItsColour) {
  // cos(2 theta): lobes along x positive, along y negative (drawn as |p| in its own colour).
  std::vector<double> p(360);
  for (std::size_t k = 0; k < p.size(); ++k) p[k] = std::cos(2 * 2 * M_PI * double(k) / 360.0);
  const fs::path png = dir_ / "polar.png";
  const Status st = write_polar_chart(
      png, {.title = "cos 2#gh", .samples = p, .positive_label = "+", .negative_label = "-"}, 300);
  ASSERT_TRUE(st) << st.message();
  const Rgba img = read_png_rgba(png);
  ASSERT_EQ(img.w, 300);
  ASSERT_EQ(img.h, 300);
  const auto is = [&](int x, int y, Rgb8 c) {
    const std::size_t i = 4 * (std::size_t(y) * std::size_t(img.w) + std::size_t(x));
    return img.px[i] == c.r && img.px[i + 1] == c.g && img.px[i + 2] == c.b;
  };
  // Each colour's extent, the legend in the lower-left corner aside: the positive lobes span
  // x, the negative ones y, both a diameter of r = 1.
  int x0 = img.w, x1 = 0, y0 = img.h, y1 = 0, pos_rows = 0;
  for (int y = 0; y < img.h; ++y)
    for (int x = 0; x < img.w; ++x) {
      if (x < img.w / 4 && y > img.h * 4 / 5) continue;
      if (is(x, y, kPolarPositiveRgb)) x0 = std::min(x0, x), x1 = std::max(x1, x), ++pos_rows;
      if (is(x, y, kPolarNegativeRgb)) y0 = std::min(y0, y), y1 = std::max(y1, y);
    }
  ASSERT_GT(pos_rows, 100);
  EXPECT_GT(x1 - x0, img.w / 2) << "the positive lobes along x";
  EXPECT_GT(y1 - y0, img.h / 2) << "the negative lobes along y, drawn as |p|";
  EXPECT_NEAR(x1 - x0, y1 - y0, 3) << "both reach r = 1";
  EXPECT_FALSE(write_polar_chart(dir_ / "p.png", {"", p, "", ""}, 10));
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
