// `ardcell texture` (the real binary): the plan line, the outputs at the final size with the
// stated bit depths (read back with libpng), the same bits on a second run, bad input (one
// line, exit 2, nothing written), and a stop signal that ends it with nothing written. Also the
// grayscale PNG writers (drivers/png_writer.h): 16-bit samples stored big-endian.
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "drivers/png_writer.h"
#include "host/io/npy.h"
#include "tests/drivers/binary_run_fixture.h"
#include "tests/drivers/png_read_back.h"
#include "tests/drivers/process_run_fixture.h"

namespace ardcell {
namespace {

namespace fs = std::filesystem;

std::string first_line(const std::string& s) { return s.substr(0, s.find('\n')); }

class TextureCli : public BinaryRunTest {
 protected:
  // Two tiny levels on the built-in periodic preset.
  static std::string small(const std::string& extra) {
    return "texture pearson --levels 16,32 --frames-per-level 3 --backend threads --quiet " + extra;
  }
  bool empty_work() const { return fs::is_empty(work()); }
};

TEST_F(TextureCli, WritesHeightNormalHeight16AndNpyAtTheFinalSize) {
  const BinaryRunResult r =
      run(small("--out t.png --normal-map n.png --height16 h16.png --npy t.npy"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(first_line(r.out).rfind("levels=16,32 frames_per_level=3 rd_steps_per_frame=", 0), 0u)
      << r.out;
  EXPECT_NE(r.out.find("size=32x32 frames=6"), std::string::npos) << r.out;
  const PngInfo t = read_png(work() / "t.png");
  ASSERT_TRUE(t.ok);
  EXPECT_EQ(t.width, 32);
  EXPECT_EQ(t.height, 32);
  EXPECT_EQ(t.bit_depth, 8);
  EXPECT_EQ(t.color_type, PNG_COLOR_TYPE_GRAY);
  // min .. max mapped to the full range.
  int lo = 255, hi = 0;
  for (const auto& row : t.rows)
    for (uint8_t v : row) lo = std::min<int>(lo, v), hi = std::max<int>(hi, v);
  EXPECT_EQ(lo, 0);
  EXPECT_EQ(hi, 255);
  const PngInfo h = read_png(work() / "h16.png");
  ASSERT_TRUE(h.ok);
  EXPECT_EQ(h.width, 32);
  EXPECT_EQ(h.bit_depth, 16);
  EXPECT_EQ(h.color_type, PNG_COLOR_TYPE_GRAY);
  // The 16-bit sample's high byte is the 8-bit one (within rounding).
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) {
      const int v16 = h.rows[std::size_t(y)][std::size_t(2 * x)] << 8 |
                      h.rows[std::size_t(y)][std::size_t(2 * x + 1)];
      ASSERT_NEAR(v16 / 257.0, t.rows[std::size_t(y)][std::size_t(x)], 0.51) << x << "," << y;
    }
  const PngInfo n = read_png(work() / "n.png");
  ASSERT_TRUE(n.ok);
  EXPECT_EQ(n.width, 32);
  EXPECT_EQ(n.bit_depth, 8);
  EXPECT_EQ(n.color_type, PNG_COLOR_TYPE_RGB);
  NpyArray npy;
  ASSERT_TRUE(read_npy(work() / "t.npy", npy));
  EXPECT_EQ(npy.nx, 32);
  EXPECT_EQ(npy.ny, 32);
}

TEST_F(TextureCli, RepeatsBitForBit) {
  ASSERT_EQ(run(small("--out a.png --npy a.npy")).code, 0);
  ASSERT_EQ(run(small("--out b.png --npy b.npy")).code, 0);
  EXPECT_EQ(slurp(work() / "a.npy"), slurp(work() / "b.npy"));
  EXPECT_EQ(slurp(work() / "a.png"), slurp(work() / "b.png"));
}

TEST_F(TextureCli, StartDoublesUpToTheSizeAndTheFieldCanBeChosen) {
  const BinaryRunResult r =
      run("texture pearson --size 32 --start 8 --frames-per-level 1 --field A --backend serial "
          "--quiet --out t.png --set rd.reaction.f=0.035");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(first_line(r.out).rfind("levels=8,16,32 frames_per_level=1", 0), 0u) << r.out;
  EXPECT_NE(first_line(r.out).find("field=A"), std::string::npos) << r.out;
  EXPECT_EQ(read_png(work() / "t.png").width, 32);
}

TEST_F(TextureCli, BadInputExitsTwoWithOneLineAndWritesNothing) {
  const std::pair<const char*, const char*> cases[] = {
      {"texture cavity-gray-scott --out t.png",
       "texture needs a periodic preset: rd.boundary = periodic, got dirichlet"},
      {"texture pearson --set rd.scheme=implicit --set rd.boundary=neumann --out t.png",
       "texture needs a periodic preset: rd.boundary = periodic, got neumann"},
      {"texture pearson --levels 32,16 --out t.png", "expected increasing sides"},
      {"texture pearson --levels 16,abc --out t.png", "not a whole number"},
      {"texture pearson --levels 4,16 --out t.png", "out of range"},
      {"texture pearson --levels 16,32 --size 64 --out t.png", "expected the last level"},
      {"texture pearson --size 4 --out t.png", "expected at least 8"},
      {"texture pearson --size 70000 --out t.png", "--size"},
      {"texture pearson --size 64x32 --out t.png", "square"},
      {"texture pearson --start 4 --size 32 --out t.png", "--start 4"},
      {"texture pearson --levels 16,32 --start 16 --out t.png", "excludes"},
      {"texture pearson --levels 16,32 --frames-per-level 0 --out t.png", "1 or more"},
      {"texture pearson --levels 16,32 --field dye --out t.png", "expected A or B"},
      {"texture pearson --levels 16,32 --out missing/t.png", "does not exist"},
      {"texture pearson --levels 16,32 --out t.png --npy t.png", "written twice"},
      {"texture pearson --levels 16,32 --out t.png --backend gpu", "--backend 'gpu'"},
      {"texture nope --out t.png", "unknown preset 'nope'"},
      {"texture pearson --levels 16,32", "--out"},
      {"texture pearson --set rd.reaction.f=7 --out t.png", "rd.reaction.f"},
  };
  for (const auto& [args, says] : cases) {
    const BinaryRunResult r = run(std::string(args) + " --quiet");
    EXPECT_EQ(r.code, 2) << args << "\n" << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << args << "\n" << r.err;
    EXPECT_EQ(r.err.rfind("ardcell texture: ", 0), 0u) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(says), std::string::npos) << args << "\n" << r.err;
    EXPECT_TRUE(empty_work()) << args;
  }
}

TEST(PngWriterGray, SixteenBitSamplesAreBigEndianAndEightBitAsGiven) {
  const fs::path dir = fresh_test_dir("ardcell_png_gray");
  ImageGray16 h16;
  h16.resize(3, 2);
  h16.pixels = {0x0102, 0xA0B0, 65535, 0, 1, 256};
  ASSERT_TRUE(write_png_gray16(dir / "h.png", h16));
  const PngInfo r = read_png(dir / "h.png");
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(r.bit_depth, 16);
  EXPECT_EQ(r.rows[0], (std::vector<uint8_t>{0x01, 0x02, 0xA0, 0xB0, 0xFF, 0xFF}));
  EXPECT_EQ(r.rows[1], (std::vector<uint8_t>{0, 0, 0, 1, 1, 0}));
  ImageGray8 h8;
  h8.resize(2, 2);
  h8.pixels = {0, 50, 200, 255};
  ASSERT_TRUE(write_png_gray8(dir / "g.png", h8));
  const PngInfo g = read_png(dir / "g.png");
  ASSERT_TRUE(g.ok);
  EXPECT_EQ(g.bit_depth, 8);
  EXPECT_EQ(g.rows[1], (std::vector<uint8_t>{200, 255}));
  EXPECT_FALSE(write_png_gray8(dir / "empty.png", ImageGray8{}));
  EXPECT_FALSE(write_png_gray16(dir / "missing" / "h.png", h16));
  EXPECT_FALSE(fs::exists(dir / "empty.png"));
  fs::remove_all(dir);
}

class TextureSignals : public ProcessRunTest {};

TEST_F(TextureSignals, AStopSignalEndsItWithNothingWritten) {
  for (const int sig : {SIGINT, SIGTERM}) {
    const pid_t pid =
        start({"texture", "pearson", "--levels", "16,32", "--frames-per-level", "100000000",
               "--backend", "threads", "--quiet", "--out", "t.png", "--normal-map", "n.png"});
    started(pid);
    ASSERT_EQ(::kill(pid, sig), 0);
    EXPECT_EQ(wait_for(pid), 128 + sig) << read("stderr");
    EXPECT_NE(read("stderr").find("nothing written"), std::string::npos) << read("stderr");
    EXPECT_FALSE(fs::exists(dir() / "t.png"));
    EXPECT_FALSE(fs::exists(dir() / "n.png"));
    EXPECT_TRUE(temporaries().empty());
  }
}

}  // namespace
}  // namespace ardcell
