// Shared by every ardcell OpenCL kernel (built first, into one program with the others).
//
// Layout: a field lives on the device with the host Field's layout: cell (x, y) at
// f[origin + y * stride + x], origin = halo * stride + halo. All fields of one launch share
// stride and origin (SimState's fields all have one size and halo 1).
//
// SPE style: a work-group plays an SPE and walks the tiles t = group, group + groups, ...; its
// __local buffers are the local store, split in two slots. async_work_group_copy is the DMA: the
// rows of tile t+groups stream into one slot while tile t computes from the other, and
// wait_group_events is the tag wait. Results are written straight to global memory (the put).
// No contraction of a * b + c into fma, as the C++ solver sweeps (kernels/stencil_sweeps.cpp,
// multigrid_solver.cpp: -ffp-contract=off in CMakeLists.txt), so both round every product and
// sum the same way. GCC contracts the other C++ kernels even in ISO C++20 mode: their twins
// agree to an ulp or so, not to the bit.
#pragma OPENCL FP_CONTRACT OFF

#if defined(cl_khr_fp64)
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
typedef double real;
#define ARDCELL_REAL_IS_DOUBLE 1
#else
typedef float real;
#define ARDCELL_REAL_IS_DOUBLE 0
#endif

typedef struct {
  int x0, y0, x1, y1;  // half-open
} box_t;

inline box_t make_box(int x0, int y0, int x1, int y1) {
  box_t b;
  b.x0 = x0;
  b.y0 = y0;
  b.x1 = x1;
  b.y1 = y1;
  return b;
}

inline int box_w(box_t b) { return b.x1 - b.x0; }
inline int box_h(box_t b) { return b.y1 - b.y0; }

inline box_t box_grow_clip(box_t b, int n, box_t lim) {
  return make_box(max(b.x0 - n, lim.x0), max(b.y0 - n, lim.y0), min(b.x1 + n, lim.x1),
                  min(b.y1 + n, lim.y1));
}

inline int tile_count(box_t region, int tw, int th) {
  return ((box_w(region) + tw - 1) / tw) * ((box_h(region) + th - 1) / th);
}

// Core of tile t of `region` cut into tw x th tiles, row-major; the last column and row take
// what is left.
inline box_t tile_core(int t, box_t region, int tw, int th) {
  const int ntx = (box_w(region) + tw - 1) / tw;
  const int x0 = region.x0 + (t % ntx) * tw;
  const int y0 = region.y0 + (t / ntx) * th;
  return make_box(x0, y0, min(x0 + tw, region.x1), min(y0 + th, region.y1));
}

// DMA get: box b of field f into dst (row pitch box_w(b)), chained onto event ev.
inline event_t fetch_box(__local float* dst, __global const float* f, int stride, int origin,
                         box_t b, event_t ev) {
  const int w = box_w(b);
  for (int y = b.y0; y < b.y1; ++y)
    ev = async_work_group_copy(dst + (y - b.y0) * w, f + origin + y * stride + b.x0, (size_t)w,
                               ev);
  return ev;
}

// Work-item lid of ls visits the cells (x, y) of box b: rows in turn, columns strided, so the
// work-items of a group touch adjacent cells (vectorisable on a CPU, coalesced on a GPU).
#define FOR_CELLS(b, x, y)                    \
  for (int y = (b).y0; y < (b).y1; ++y)      \
    for (int x = (b).x0 + lid; x < (b).x1; x += ls)

// Index of global cell (x, y) in a local copy of box b.
inline int local_index(box_t b, int x, int y) { return (y - b.y0) * box_w(b) + (x - b.x0); }
inline int global_index(int stride, int origin, int x, int y) { return origin + y * stride + x; }

// Issues the gets of tile t of `region` (cores tw x th, read box = core grown by `halo`, clipped
// to `lim`) for up to three fields into slot `slot` of lbuf: field i lands at
// lbuf + slot * slot_floats + i * field_floats, row pitch = the read box's width.
// Nothing is issued when t >= nt (the event is then not waited on).
inline event_t spe_get(int t, int nt, box_t region, int tw, int th, int halo, box_t lim,
                       __local float* lbuf, int slot_floats, int field_floats, int slot, int nf,
                       __global const float* f0, __global const float* f1,
                       __global const float* f2, int stride, int origin) {
  event_t ev = 0;
  if (t < nt) {
    const box_t rd = box_grow_clip(tile_core(t, region, tw, th), halo, lim);
    __local float* d = lbuf + slot * slot_floats;
    ev = fetch_box(d, f0, stride, origin, rd, ev);
    if (nf > 1) ev = fetch_box(d + field_floats, f1, stride, origin, rd, ev);
    if (nf > 2) ev = fetch_box(d + 2 * field_floats, f2, stride, origin, rd, ev);
  }
  return ev;
}
