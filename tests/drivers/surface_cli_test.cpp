// `ardcell surface` (the real binary): a PLY of the limit surface with the field as vertex
// colours from the built-in meshes, from an OBJ or OFF file and from the figure eight of Debian's
// libcgal-demo, the texture atlas with its UV-mapped OBJ, stable fluids' dye, and bad input as
// one line, exit 2, nothing written.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "tests/drivers/binary_run_fixture.h"

namespace ardcell {
namespace {

namespace fs = std::filesystem;

class SurfaceCli : public BinaryRunTest {
 protected:
  // The PLY's vertex and face counts from its header, and that the body has their size.
  void expect_ply(const fs::path& path, long long vertices, long long faces) {
    const std::string ply = slurp(path);
    const auto end = ply.find("end_header\n");
    ASSERT_NE(end, std::string::npos);
    const std::string header = ply.substr(0, end);
    EXPECT_EQ(header.rfind("ply\nformat binary_little_endian 1.0\n", 0), 0u);
    EXPECT_NE(header.find("element vertex " + std::to_string(vertices) + "\n"), std::string::npos)
        << header;
    EXPECT_NE(header.find("element face " + std::to_string(faces) + "\n"), std::string::npos);
    EXPECT_NE(header.find("property uchar red"), std::string::npos);
    const std::size_t body = ply.size() - (end + std::strlen("end_header\n"));
    EXPECT_EQ(body, std::size_t(vertices * 27 + faces * 17));
  }
  bool only_file(const char* name) const {
    int count = 0;
    for (const auto& e : fs::directory_iterator(work()))
      count += e.path().filename() != name ? 100 : 1;
    return count == 1;
  }
};

TEST_F(SurfaceCli, BuiltInTorusToPly) {
  const BinaryRunResult r = run("surface --patch-cells 4 --steps 20 --out t.ply");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out.rfind("patches=32 cells=512 ", 0), 0u) << r.out;
  EXPECT_NE(r.out.find("steps=20 "), std::string::npos) << r.out;
  expect_ply(work() / "t.ply", 32 * 25, 32 * 16);
  EXPECT_TRUE(only_file("t.ply"));  // no temporary left behind
}

// Multigrid solves the same steps: the same pattern as Jacobi to the solves' tolerance.
TEST_F(SurfaceCli, MultigridSolvesTheSameSteps) {
  const char* common = "surface --patch-cells 8 --steps 40 --reaction implicit --tolerance 1e-10 ";
  const BinaryRunResult jacobi = run(std::string(common) + "--out j.ply");
  const BinaryRunResult mg = run(std::string(common) + "--solver mg --out m.ply");
  ASSERT_EQ(jacobi.code, 0) << jacobi.err;
  ASSERT_EQ(mg.code, 0) << mg.err;
  EXPECT_EQ(jacobi.out.find("mean_cycles="), std::string::npos) << jacobi.out;
  EXPECT_NE(mg.out.find(" mean_cycles="), std::string::npos) << mg.out;
  EXPECT_EQ(jacobi.err, "");
  EXPECT_EQ(mg.err, "");
  // A step over hundreds of cells: Jacobi diverges and says so once; multigrid converges.
  const char* stiff = "surface --patch-cells 8 --steps 3 --dt 100 --scale 2 --reaction implicit ";
  const BinaryRunResult jacobi_stiff = run(std::string(stiff) + "--out js.ply");
  EXPECT_EQ(jacobi_stiff.code, 0);
  EXPECT_EQ(count_lines(jacobi_stiff.err), 1) << jacobi_stiff.err;
  EXPECT_NE(jacobi_stiff.err.find("ardcell surface: step 1: the implicit diffusion stopped at"),
            std::string::npos)
      << jacobi_stiff.err;
  EXPECT_NE(jacobi_stiff.err.find("--solver mg"), std::string::npos) << jacobi_stiff.err;
  const BinaryRunResult mg_stiff = run(std::string(stiff) + "--solver mg --out ms.ply");
  EXPECT_EQ(mg_stiff.code, 0);
  EXPECT_EQ(mg_stiff.err, "");
  // The chemicals' ranges, printed to 4 digits, agree.
  const auto ranges = [](const std::string& out) {
    const std::size_t from = out.find(" a=[");
    return out.substr(from, out.find(" out=") - from);
  };
  EXPECT_EQ(ranges(jacobi.out), ranges(mg.out)) << jacobi.out << mg.out;
}

TEST_F(SurfaceCli, AtlasIsAnObjAMaterialAndAPng) {
  const BinaryRunResult r =
      run("surface --shape genus2 --patch-cells 4 --steps 20 --atlas t --render r.png --view 0,90");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("out=- atlas=t.obj render=r.png"), std::string::npos) << r.out;
  const std::string render = slurp(work() / "r.png");
  ASSERT_GE(render.size(), 24u);
  EXPECT_EQ(render.substr(1, 3), "PNG");
  // The double torus's 50 patches: 8 tiles a row, 7 rows, tiles of 4 + 2 texels.
  const std::string png = slurp(work() / "t.png");
  ASSERT_GE(png.size(), 24u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  const auto be32 = [&](std::size_t at) {
    return (unsigned(uint8_t(png[at])) << 24) | (unsigned(uint8_t(png[at + 1])) << 16) |
           (unsigned(uint8_t(png[at + 2])) << 8) | unsigned(uint8_t(png[at + 3]));
  };
  EXPECT_EQ(be32(16), 48u);  // IHDR width
  EXPECT_EQ(be32(20), 42u);  // and height
  const std::string obj = slurp(work() / "t.obj");
  EXPECT_NE(obj.find("mtllib t.mtl\nusemtl ardcell_field\n"), std::string::npos);
  std::size_t faces = 0, vertices = 0;
  for (std::size_t at = 0; (at = obj.find('\n', at)) != std::string::npos; ++at) {
    faces += obj.compare(at + 1, 2, "f ") == 0;
    vertices += obj.compare(at + 1, 2, "v ") == 0;
  }
  EXPECT_EQ(faces, 50u * 16u);
  EXPECT_EQ(vertices, 50u * 25u);
  EXPECT_NE(slurp(work() / "t.mtl").find("map_Kd t.png\n"), std::string::npos);
}

TEST_F(SurfaceCli, MixedObjIsRefinedOnce) {
  // A square pyramid: one quad and four triangles, 16 quads after one refinement.
  std::ofstream(work() / "p.obj")
      << "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nv 0 0 1.5\n"
         "f 4/1/1 3/1/1 2/1/1 1/1/1\nf 1 2 5\nf 2 3 5\nf 3//1 4//1 5//1\n"
         "f -2 -5 -1\n";
  const BinaryRunResult r =
      run("surface --mesh p.obj --patch-cells 4 --steps 5 --reaction implicit --field a "
          "--out p.ply");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out.rfind("patches=16 (refined once) cells=256 ", 0), 0u) << r.out;
  expect_ply(work() / "p.ply", 16 * 25, 16 * 16);
}

// The same pyramid as OFF (0-based, the header's counts, a colour after a face): the same
// patches.
TEST_F(SurfaceCli, OffMeshIsReadAsObjIs) {
  std::ofstream(work() / "p.off") << "OFF\n5 5 8\n-1 -1 0\n1 -1 0\n1 1 0\n-1 1 0\n0 0 1.5\n"
                                     "4 3 2 1 0\n3 0 1 4 255 0 0\n3 1 2 4\n3 2 3 4\n3 3 0 4\n";
  const BinaryRunResult r = run("surface --mesh p.off --patch-cells 4 --steps 5 --out p.ply");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out.rfind("patches=16 (refined once) cells=256 ", 0), 0u) << r.out;
  expect_ply(work() / "p.ply", 16 * 25, 16 * 16);
}

// --shape eight: CGAL's figure eight from libcgal-demo (634 triangles, 1902 patches), skipped
// only without the package; without its file (ARDCELL_MESH_DIR naming an empty folder) the
// shape names the file it looked for and what to do, one line, exit 2.
TEST_F(SurfaceCli, PackagedEightToPly) {
  const bool packaged = fs::exists(fs::path(ARDCELL_MESH_DIR) / "eight.off");
  if (!packaged) {
    EXPECT_FALSE(fs::exists(ARDCELL_CGAL_DATA_ARCHIVE)) << ARDCELL_MESH_DIR
        "/eight.off is missing though libcgal-demo is installed: run cmake "
        "again";
  } else {
    // The compiled-in folder, whatever the environment says.
    const BinaryRunResult r = run_command("env -u ARDCELL_MESH_DIR '" ARDCELL_BINARY
                                          "' surface --shape eight --patch-cells 2 --steps 5 "
                                          "--out e.ply");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.out.rfind("patches=1902 (refined once) cells=7608 ", 0), 0u) << r.out;
    expect_ply(work() / "e.ply", 1902 * 9, 1902 * 4);
  }
  fs::create_directories(work() / "empty");
  for (const char* shape : {"eight", "elephant"}) {
    const BinaryRunResult r =
        run_command("ARDCELL_MESH_DIR=empty exec '" ARDCELL_BINARY "' surface --shape " +
                    std::string(shape) + " --out x.ply");
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_EQ(r.err, "ardcell surface: --shape " + std::string(shape) + ": empty/" + shape +
                         ".off not found (install Debian's libcgal-demo and run cmake again, or "
                         "set ARDCELL_MESH_DIR to a folder holding " +
                         shape + ".off)\n");
    EXPECT_FALSE(fs::exists(work() / "x.ply"));
  }
  if (!packaged) GTEST_SKIP() << "needs Debian's libcgal-demo (" ARDCELL_CGAL_DATA_ARCHIVE ")";
}

// A flat scene's reaction-diffusion on the torus: Meinhardt's spots grow from the preset's noisy
// start (a spreads from 1.6 +- 5% to more than +-0.2), FitzHugh-Nagumo's waves are excited.
TEST_F(SurfaceCli, PresetsRunTheirModelOnTheSurface) {
  const auto a_range = [](const std::string& out) {
    double lo = 0, hi = 0;
    const auto at = out.find(" a=[");
    if (at == std::string::npos || std::sscanf(out.c_str() + at, " a=[%lf, %lf]", &lo, &hi) != 2)
      return -1.0;
    return hi - lo;
  };
  BinaryRunResult r =
      run("surface --preset meinhardt-spots --patch-cells 8 --steps 400 --out m.ply");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find(" model=meinhardt preset=meinhardt-spots dt=1 reaction=implicit "),
            std::string::npos)
      << r.out;
  EXPECT_GT(a_range(r.out), 0.4) << r.out;
  expect_ply(work() / "m.ply", 32 * 81, 32 * 64);
  r = run("surface --preset cavity-fhn --patch-cells 8 --steps 100 --out f.ply");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find(" model=fitzhugh-nagumo "), std::string::npos) << r.out;
  EXPECT_GT(a_range(r.out), 1.0) << r.out;
}

// Stable fluids (--fluid): the dye from the patches' sources, written as the field; the summary
// gives the projection's V-cycles, the dye's range and the divergence left.
TEST_F(SurfaceCli, FluidCarriesDyeFromTheSources) {
  const BinaryRunResult r =
      run("surface --fluid walk --patch-cells 4 --steps 10 --viscosity 0.01 --out f.ply "
          "--render f.png");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  EXPECT_EQ(r.out.rfind("patches=32 cells=512 ", 0), 0u) << r.out;
  EXPECT_NE(r.out.find(" fluid=walk dt=0.05 force=1 viscosity=0.01 "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("steps=10 mean_cycles="), std::string::npos) << r.out;
  double lo = -1, hi = -1;
  const auto at = r.out.find(" s=[");
  ASSERT_NE(at, std::string::npos) << r.out;
  ASSERT_EQ(std::sscanf(r.out.c_str() + at, " s=[%lf, %lf]", &lo, &hi), 2) << r.out;
  EXPECT_GE(lo, 0.0);
  EXPECT_GT(hi, 0.2);  // 10 steps of 0.05 at the sources, carried a little
  EXPECT_LE(hi, 1.0);
  expect_ply(work() / "f.ply", 32 * 25, 32 * 16);
  EXPECT_EQ(slurp(work() / "f.png").substr(1, 3), "PNG");
  EXPECT_NE(r.out.find(" out=f.ply render=f.png"), std::string::npos) << r.out;
}

// Two tori side by side, written as an OBJ: a surface in two pieces.
void write_two_tori(const std::filesystem::path& path) {
  std::ofstream two(path);
  for (int piece = 0; piece < 2; ++piece)
    for (int a = 0; a < 4; ++a)
      for (int t = 0; t < 3; ++t) {
        const double u = 2 * 3.14159265358979 * a / 4, v = 2 * 3.14159265358979 * t / 3;
        two << "v " << (2 + std::cos(v)) * std::cos(u) + 10 * piece << ' '
            << (2 + std::cos(v)) * std::sin(u) << ' ' << std::sin(v) << '\n';
      }
  for (int piece = 0; piece < 2; ++piece)
    for (int a = 0; a < 4; ++a)
      for (int t = 0; t < 3; ++t) {
        const auto vertex = [&](int da, int dt) {
          return 1 + 12 * piece + ((a + da) % 4) * 3 + (t + dt) % 3;
        };
        two << "f " << vertex(0, 0) << ' ' << vertex(1, 0) << ' ' << vertex(1, 1) << ' '
            << vertex(0, 1) << '\n';
      }
}

// A mesh of two pieces: the projection fixes a pressure constant on each, and the flow is
// divergence-free on both.
TEST_F(SurfaceCli, FluidRunsOnASurfaceOfTwoPieces) {
  write_two_tori(work() / "two.obj");
  const BinaryRunResult r =
      run("surface --fluid gravity --mesh two.obj --patch-cells 4 --steps 5 --out f.ply");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  EXPECT_EQ(r.out.rfind("patches=24 cells=384 ", 0), 0u) << r.out;
  double max_div = -1;
  const auto at = r.out.find(" max_div=");
  ASSERT_NE(at, std::string::npos) << r.out;
  ASSERT_EQ(std::sscanf(r.out.c_str() + at, " max_div=%lf", &max_div), 1) << r.out;
  EXPECT_LT(max_div, 1e-4) << r.out;
  EXPECT_TRUE(std::filesystem::exists(work() / "f.ply"));
}

// --down is a direction: 1e200,0,0 is 1,0,0 (scaled before its length is taken), the same run
// to the bit; and --conserve-dye keeps the dye within [0, 1] (its range in the summary).
TEST_F(SurfaceCli, FluidDownIsADirectionAndConservedDyeStaysWithinOne) {
  const auto summary = [&](const std::string& args) {
    const BinaryRunResult r = run("surface --fluid gravity --patch-cells 4 --steps 20 --force 4 " +
                                  args + " --out f.ply");
    EXPECT_EQ(r.code, 0) << args << "\n" << r.err;
    EXPECT_EQ(r.err, "") << args;
    const auto at = r.out.find("mean_cycles=");
    const auto end = r.out.find(" out=");
    EXPECT_NE(at, std::string::npos) << r.out;
    EXPECT_NE(end, std::string::npos) << r.out;
    // The summary but the wall clock.
    std::string line = r.out.substr(at, end - at);
    const auto s0 = line.find(" seconds="), s1 = line.find(" s=[");
    return line.erase(s0, s1 - s0);
  };
  const std::string unit = summary("--down 1,0,0");
  EXPECT_EQ(summary("--down 1e200,0,0"), unit);
  EXPECT_NE(summary("--down 0,0,-1"), unit);
  const std::string conserved = summary("--down 1,0,0 --conserve-dye");
  double lo = -1, hi = -1;
  const auto at = conserved.find(" s=[");
  ASSERT_NE(at, std::string::npos) << conserved;
  ASSERT_EQ(std::sscanf(conserved.c_str() + at, " s=[%lf, %lf]", &lo, &hi), 2) << conserved;
  EXPECT_GE(lo, 0.0) << conserved;
  EXPECT_LE(hi, 1.0) << conserved;
}

TEST_F(SurfaceCli, PresetsASurfaceCannotRunAreRefused) {
  const struct {
    const char* args;
    const char* line;
  } cases[] = {
      {"--preset cavity",
       "ardcell surface: --preset cavity: rd.enabled is false (expected a "
       "scene with RD)\n"},
      {"--preset fig3-orient",
       "ardcell surface: --preset fig3-orient: rd.anisotropy: the "
       "surface's diffusion is isotropic (expected isotropic)\n"},
      {"--preset meinhardt-spots --F 0.05",
       "ardcell surface: --F: the preset sets the reaction (expected no --F with --preset)\n"},
  };
  for (const auto& c : cases) {
    const BinaryRunResult r = run(std::string("surface --out x.ply ") + c.args);
    EXPECT_EQ(r.code, 2) << c.args;
    EXPECT_EQ(r.err, c.line) << c.args;
  }
}

TEST_F(SurfaceCli, BadInputIsOneLineAndWritesNothing) {
  std::ofstream(work() / "bad.obj") << "v 0 0 0\nv 1 0 0\nf 1 2 3\n";
  std::ofstream(work() / "bad.off") << "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n";
  std::ofstream(work() / "fin.obj") << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 1 0 1\nv 0 0 1\n"
                                       "v 1 0 -1\nv 0 0 -1\nf 1 2 3 4\nf 2 1 6 5\nf 1 2 7 8\n";
  std::ofstream(work() / "point.obj") << "v 0 0 0\nv 0 0 0\nv 0 0 0\nv 0 0 0\nv 0 0 0\n"
                                         "v 0 0 0\nv 0 0 0\nv 0 0 0\nf 1 4 3 2\nf 5 6 7 8\n"
                                         "f 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
  const std::pair<const char*, const char*> cases[] = {
      {"surface --patch-cells 12 --out x.ply",
       "ardcell surface: --patch-cells 12: expected a power of two in 2..1024\n"},
      {"surface --mesh bad.obj --out x.ply",
       "ardcell surface: bad.obj: line 3: face index 3 names no vertex (2 so far)\n"},
      {"surface --mesh fin.obj --out x.ply",
       "ardcell surface: fin.obj: non-manifold edge 1-2: shared by 3 or more faces (1, 2, 3)\n"},
      {"surface --mesh missing.obj --out x.ply", nullptr},
      {"surface --mesh point.obj --patch-cells 2 --out x.ply",
       "ardcell surface: point.obj: the limit surface is degenerate (no tangent plane) in patch 1 "
       "at (0.25, 0): coincident or folded control points?\n"},
      {"surface --shape klein --out x.ply",
       "ardcell surface: --shape 'klein': expected torus, cube-sphere, genus2, eight or "
       "elephant\n"},
      {"surface --mesh bad.off --out x.ply",
       "ardcell surface: bad.off: line 6: face 0: index 3 names no vertex (3 in the file)\n"},
      {"surface --reaction rk4 --out x.ply",
       "ardcell surface: --reaction 'rk4': expected euler (the seed's) or implicit\n"},
      {"surface --solver cg --out x.ply",
       "ardcell surface: --solver 'cg': expected jacobi (the seed's sweeps) or mg\n"},
      {"surface --patch-cells 1024 --out x.ply", nullptr},
      {"surface --out no/such/folder/x.ply", nullptr},
      {"surface --atlas no/such/folder/x", nullptr},
      {"surface --steps 1",
       "ardcell surface: nothing to write: expected --out FILE.ply, --atlas PREFIX or --render "
       "FILE.png\n"},
      {"surface --render x.png --view 10",
       "ardcell surface: --view '10': expected AZIMUTH,ELEVATION in degrees, elevation in "
       "-90..90\n"},
      {"surface --fluid swirl --out x.ply",
       "ardcell surface: --fluid 'swirl': expected gravity or walk\n"},
      {"surface --fluid gravity --F 0.05 --out x.ply",
       "ardcell surface: --F: a reaction-diffusion setting (expected no --F with --fluid)\n"},
      {"surface --viscosity 1 --out x.ply",
       "ardcell surface: --viscosity: a fluid setting (expected --fluid gravity or walk)\n"},
      {"surface --fluid gravity --down 0,0,0 --out x.ply",
       "ardcell surface: --down '0,0,0': expected X,Y,Z, a finite direction (not 0,0,0)\n"},
      {"surface --fluid gravity --down 1e999,0,0 --out x.ply",
       "ardcell surface: --down '1e999,0,0': expected X,Y,Z, a finite direction (not 0,0,0)\n"},
      {"surface --fluid gravity --down nan,0,1 --out x.ply",
       "ardcell surface: --down 'nan,0,1': expected X,Y,Z, a finite direction (not 0,0,0)\n"},
      {"surface --fluid walk --down 0,0,1 --out x.ply",
       "ardcell surface: --down: a gravity setting (expected no --down with --fluid walk)\n"},
      {"surface --fluid gravity --conserve-dye=2 --out x.ply",
       "ardcell surface: --conserve-dye: expected no value, true or false, got '2' (see ardcell "
       "surface --help)\n"},
      {"surface --render x.png --view 10,95",
       "ardcell surface: --view '10,95': expected AZIMUTH,ELEVATION in degrees, elevation in "
       "-90..90\n"},
  };
  for (const auto& [args, message] : cases) {
    const BinaryRunResult r = run(args);
    EXPECT_EQ(r.code, 2) << args << "\n" << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << args << "\n" << r.err;
    EXPECT_EQ(r.err.rfind("ardcell surface: ", 0), 0u) << r.err;
    if (message) {
      EXPECT_EQ(r.err, message) << args;
    }
    EXPECT_FALSE(fs::exists(work() / "x.ply")) << args;
    EXPECT_FALSE(fs::exists(work() / "x.png")) << args;
  }
}

}  // namespace
}  // namespace ardcell
