// The kernels of a frame give the same bits whatever the layout of the fields they run on: a
// field's halo width and origin move where its cells sit relative to cache lines and SIMD
// vectors (a block of a decomposed grid has a deep halo, runtime/block_layout.h), so a kernel
// whose result depended on that would break the blocks' bit-for-bit equality with one grid.
#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <random>

#include "kernels/advect.h"
#include "kernels/project.h"
#include "kernels/reaction.h"
#include "kernels/sources.h"
#include "kernels/stam_sweeps.h"
#include "runtime/boundary.h"
#include "runtime/field.h"

namespace ardcell {
namespace {

constexpr Int2 kGrid{77, 41};

// The same random values over interior + ring, in a field of halo `halo`.
FieldF random_cells(int halo, unsigned seed, float lo, float hi) {
  FieldF f(kGrid, halo);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> d(lo, hi);
  const Box2 b = f.interior().grown(1);
  for (int y = b.min.y; y < b.max.y; ++y)
    for (int x = b.min.x; x < b.max.x; ++x) f(x, y) = d(rng);
  return f;
}

bool same_interior(const FieldF& a, const FieldF& b) {
  const Box2 box = a.interior().grown(1);
  for (int y = box.min.y; y < box.max.y; ++y)
    if (std::memcmp(a.row(y) + box.min.x, b.row(y) + box.min.x,
                    std::size_t(box.width()) * sizeof(float)) != 0)
      return false;
  return true;
}

struct Fields {
  explicit Fields(int halo)
      : u(random_cells(halo, 1, -2.0f, 2.0f)),
        v(random_cells(halo, 2, -2.0f, 2.0f)),
        q(random_cells(halo, 3, 0.0f, 1.0f)),
        a(random_cells(halo, 4, 0.2f, 1.0f)),
        b(random_cells(halo, 5, 0.0f, 0.5f)),
        out(kGrid, halo),
        out2(kGrid, halo) {}
  FieldF u, v, q, a, b, out, out2;
};

// Every kernel, in turn, on fields of halo 1 and of deeper halos.
template <class Kernel>
void expect_layout_free(const char* name, Kernel kernel) {
  Fields ref(1);
  kernel(ref);
  for (int halo : {2, 7, 23, 33}) {
    Fields r(halo);
    kernel(r);
    EXPECT_TRUE(same_interior(r.out, ref.out)) << name << ", halo " << halo;
    EXPECT_TRUE(same_interior(r.out2, ref.out2)) << name << ", halo " << halo;
  }
}

TEST(FieldLayout, KernelsGiveTheSameBitsForAnyHalo) {
  const Box2 all = box_of_size(kGrid);
  expect_layout_free("stam_jacobi_sweep", [&](Fields& r) {
    stam_jacobi_sweep(r.q.view(), r.u.view(), r.out.view(), all,
                      StamSweepParams{0.7f, 1.0f / 3.8f});
  });
  expect_layout_free("pressure_rhs", [&](Fields& r) {
    pressure_rhs(r.u.view(), r.v.view(), r.out.view(), all, ProjectParams{0.01f});
  });
  expect_layout_free("subtract_gradient", [&](Fields& r) {
    copy_box<float>(r.u.view(), r.out.view(), r.u.with_halo());
    copy_box<float>(r.v.view(), r.out2.view(), r.v.with_halo());
    subtract_gradient(r.q.view(), r.out.view(), r.out2.view(), all, ProjectParams{0.01f});
  });
  expect_layout_free("add_splat", [&](Fields& r) {
    copy_box<float>(r.q.view(), r.out.view(), r.q.with_halo());
    add_splat(r.out.view(), all, SplatParams{30.2f, 17.6f, 6.0f, 0.3f});
  });
  expect_layout_free("advect_fields", [&](Fields& r) {
    const std::array<View<const float>, 2> in{r.q.view(), r.a.view()};
    const std::array<View<float>, 2> out{r.out.view(), r.out2.view()};
    advect_fields(r.u.view(), r.v.view(), in, out, all, AdvectParams{1.7f, kGrid, false});
  });
  // Departure points just below a cell (x - 2^-22 for x = 2, 3): where a shift by the view's
  // first cell before truncating would round up into the next cell.
  expect_layout_free("advect_fields, departures just below a cell", [&](Fields& r) {
    r.u.fill(0x1p-22f);
    r.v.fill(0.0f);
    const std::array<View<const float>, 1> in{r.q.view()};
    const std::array<View<float>, 1> out{r.out.view()};
    advect_fields(r.u.view(), r.v.view(), in, out, all, AdvectParams{1.0f, kGrid, false});
  });
  expect_layout_free("gray_scott_implicit_tile", [&](Fields& r) {
    gray_scott_implicit_tile(r.a.view(), r.b.view(), r.out.view(), r.out2.view(), all,
                             GrayScottImplicitParams{0.04f, 0.06f, 1.0f});
  });
  expect_layout_free("fill_boundary", [&](Fields& r) {
    copy_box<float>(r.q.view(), r.out.view(), r.q.with_halo());
    fill_boundary(r.out.view(), kGrid, BoundaryFill::stam(1));
  });
}

}  // namespace
}  // namespace ardcell
