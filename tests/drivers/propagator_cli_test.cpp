// `ardcell propagator` (the real binary): Fig. 1's lobes for the Table 2 sequences (b) 90/270,
// (c) 45/165/285, (d) the axes, (e) the diagonals, none for the isotropic (a); explicit
// components; the PNG's size; a negative Gram-Charlier value drawn in its own colour; bad input
// (one line, exit 2, no file).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "drivers/chart.h"
#include "tests/drivers/binary_run_fixture.h"
#include "tests/drivers/png_read_back.h"

namespace ardcell {
namespace {

namespace fs = std::filesystem;

// The degrees of "maxima_deg=45,165,285 ..." (empty for "none"); NaN entries when unparsable.
std::vector<double> maxima(const std::string& out) {
  std::vector<double> deg;
  const std::size_t at = out.find("maxima_deg=");
  if (at == std::string::npos) return {std::nan("")};
  std::string list = out.substr(at + 11);
  list = list.substr(0, list.find_first_of(" \n"));
  if (list == "none") return deg;
  std::stringstream in(list);
  std::string item;
  while (std::getline(in, item, ',')) {
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    deg.push_back(*end == '\0' ? v : std::nan(""));
  }
  return deg;
}

void expect_maxima(const std::string& out, const std::vector<double>& want) {
  const std::vector<double> got = maxima(out);
  ASSERT_EQ(got.size(), want.size()) << out;
  for (std::size_t i = 0; i < want.size(); ++i) EXPECT_NEAR(got[i], want[i], 1.0) << out;
}

class PropagatorCli : public BinaryRunTest {};

TEST_F(PropagatorCli, Table2LobesAreWhereFigure1HasThem) {
  const std::pair<const char*, std::vector<double>> cases[] = {
      {"a", {}},
      {"b", {90, 270}},
      {"c", {45, 165, 285}},
      {"d", {0, 90, 180, 270}},
      {"e", {45, 135, 225, 315}},
      {"f", {90, 270}},
  };
  for (const auto& [letter, want] : cases) {
    const BinaryRunResult r = run(std::string("propagator ") + letter + " --out p.png");
    ASSERT_EQ(r.code, 0) << letter << "\n" << r.err;
    EXPECT_EQ(count_lines(r.out), 1) << r.out;
    EXPECT_TRUE(r.err.empty()) << r.err;
    expect_maxima(r.out, want);
    EXPECT_NE(r.out.find("lobes=" + std::to_string(want.size())), std::string::npos) << r.out;
    const PngInfo png = read_png(work() / "p.png");
    ASSERT_TRUE(png.ok) << letter;
    EXPECT_EQ(png.width, 512);
    EXPECT_EQ(png.height, 512);
    EXPECT_EQ(png.bit_depth, 8);
    EXPECT_EQ(png.color_type, PNG_COLOR_TYPE_RGB);
  }
}

TEST_F(PropagatorCli, ExplicitComponentsMatchTheirTable2Letter) {
  const BinaryRunResult d = run("propagator d --out d.png --size 128");
  const BinaryRunResult k =
      run("propagator xx=1,yy=1,xxxx=1,xxyy=-1,yyyy=1 --out k.png --size 128");
  ASSERT_EQ(d.code, 0) << d.err;
  ASSERT_EQ(k.code, 0) << k.err;
  // The same numbers; only the out= path and the title differ.
  EXPECT_EQ(d.out.substr(0, d.out.find(" out=")), k.out.substr(0, k.out.find(" out=")));
  EXPECT_EQ(read_png(work() / "k.png").width, 128);
  // Symmetric tensors: the index order does not matter ("yx" is xy, "yxx" is xxy).
  const BinaryRunResult c = run("propagator c --out c.png --size 64");
  const BinaryRunResult p =
      run("propagator yy=1,xx=1,xxx=1,yxx=-1,yxy=-1,yyy=1 --out p.png --size 64");
  ASSERT_EQ(p.code, 0) << p.err;
  EXPECT_EQ(c.out.substr(0, c.out.find(" out=")), p.out.substr(0, p.out.find(" out=")));
}

TEST_F(PropagatorCli, NegativeValuesAreDrawnInTheirOwnColour) {
  // At a long tau the rank-4 term outweighs the Gaussian on the axes: p < 0 there.
  const BinaryRunResult r =
      run("propagator xx=1,yy=1,xxxx=-3,xxyy=3,yyyy=-3 --tau 1 --out n.png --size 256");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("negative=yes"), std::string::npos) << r.out;
  expect_maxima(r.out, {45, 135, 225, 315});
  const PngInfo png = read_png(work() / "n.png");
  ASSERT_TRUE(png.ok);
  int negative = 0;
  for (const auto& row : png.rows)
    for (std::size_t i = 0; i + 2 < row.size(); i += 3)
      if (row[i] == kPolarNegativeRgb.r && row[i + 1] == kPolarNegativeRgb.g &&
          row[i + 2] == kPolarNegativeRgb.b)
        ++negative;
  EXPECT_GT(negative, 50);
  // Fig. 1's own sequences stay positive at tau = 0.1.
  const BinaryRunResult e = run("propagator e --out e.png --size 64");
  EXPECT_NE(e.out.find("negative=no"), std::string::npos) << e.out;
}

TEST_F(PropagatorCli, BadInputExitsTwoWithOneLineAndWritesNothing) {
  const std::pair<const char*, const char*> cases[] = {
      {"propagator g --out p.png", "'g' is not key=value"},
      {"propagator xz=1 --out p.png", "unknown tensor component 'xz'"},
      {"propagator xx=1,yy=1,xxxxx=1 --out p.png", "unknown tensor component 'xxxxx'"},
      {"propagator x=1,yy=1 --out p.png", "unknown tensor component 'x'"},
      {"propagator xx=abc,yy=1 --out p.png", "xx='abc' (expected a finite number)"},
      {"propagator xx=nan,yy=1 --out p.png", "expected a finite number"},
      {"propagator xx=1,xx=2,yy=1 --out p.png", "given twice"},
      {"propagator xx=1,yy=-1 --out p.png", "positive definite"},
      {"propagator xxxx=1 --out p.png", "positive definite"},
      {"propagator c --out missing/p.png", "does not exist"},
      {"propagator c --out p.bmp", "expected a .png or .svg file"},
      {"propagator c", "--out"},
      {"propagator --out p.png", "sequence"},
      {"propagator c --out p.png --tau 0", "--tau"},
      {"propagator c --out p.png --tau nan", "--tau"},
      {"propagator c --out p.png --radius -1", "--radius"},
      {"propagator c --out p.png --size 10", "--size"},
  };
  for (const auto& [args, says] : cases) {
    const BinaryRunResult r = run(args);
    EXPECT_EQ(r.code, 2) << args << "\n" << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << args << "\n" << r.err;
    EXPECT_EQ(r.err.rfind("ardcell propagator: ", 0), 0u) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(says), std::string::npos) << args << "\n" << r.err;
    EXPECT_TRUE(r.out.empty()) << args << "\n" << r.out;
    EXPECT_TRUE(fs::is_empty(work())) << args;
  }
}

}  // namespace
}  // namespace ardcell
