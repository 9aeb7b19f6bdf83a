#if defined(ARDCELL_WITH_OPENCL)
#include "kernels/cl/opencl_fft.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <iterator>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "runtime/check.h"

namespace ardcell {

namespace {

// The largest prime factor of n (n >= 1).
int largest_prime_factor(int n) {
  int largest = 1;
  for (int p = 2; p * p <= n; ++p)
    while (n % p == 0) largest = p, n /= p;
  return std::max(largest, n);
}

// fft.cl's radices for a length whose prime factors are 2, 3, 5, 7, in pass order: the power of
// two in passes of 16 (fewest passes: each reads and writes every element once), the rest of it
// in one pass of 8, 4 or 2, then the odd radices. Length 1: one pass of radix 1 (a copy between
// the layouts).
std::vector<int> fft_radices(int n) {
  std::vector<int> radices;
  while (n % 16 == 0) radices.push_back(16), n /= 16;
  for (int p : {8, 4, 2})
    if (n % p == 0) radices.push_back(p), n /= p;
  for (int p : {3, 5, 7})
    while (n % p == 0) radices.push_back(p), n /= p;
  ARDCELL_CHECK(n == 1, "fft_radices: a prime factor above 7");
  if (radices.empty()) radices.push_back(1);
  return radices;
}

// w_n^k = exp(-2 pi i k / n), k < n, in double, rounded to float once.
OpenClBuffer upload_roots(OpenClContext& ctx, int n) {
  std::vector<float> roots(std::size_t(2 * n));
  for (int k = 0; k < n; ++k) {
    const double angle = -2.0 * std::numbers::pi * double(k) / double(n);
    roots[std::size_t(2 * k)] = float(std::cos(angle));
    roots[std::size_t(2 * k + 1)] = float(std::sin(angle));
  }
  OpenClBuffer buffer = ctx.allocate(roots.size() * sizeof(float));
  ctx.write(buffer, roots.data(), roots.size() * sizeof(float));
  return buffer;
}

// The passes' work-group shape (see ClFft2d::run).
constexpr std::size_t kGroupColumns = 16, kGroupRows = 4;

}  // namespace

std::string device_fft_size_problem(Int2 size) {
  // The kernels index in int: ETDRK4's coefficient tables hold 12 (nx / 2 + 1) ny complex
  // values (spectral.cl), the largest buffer a transform's user indexes.
  if (size.x >= 1 && size.y >= 1 &&
      12.0 * (size.x / 2 + 1) * double(size.y) > double(std::numeric_limits<int>::max()))
    return std::to_string(size.x) + "x" + std::to_string(size.y) +
           " is beyond the device FFT's int indices";
  for (int n : {size.x, size.y}) {
    if (n < 1) return std::to_string(n) + " is not a length";
    const int p = largest_prime_factor(n);
    if (p > 7) {
      char line[96];
      std::snprintf(line, sizeof line, "%d has a prime factor the device FFT lacks (%d)", n, p);
      return line;
    }
  }
  return "";
}

// --- ClFft2d -----------------------------------------------------------------------------------

ClFft2d::ClFft2d(OpenClContext& ctx, Int2 size, int batch) : ctx_(ctx), size_(size), batch_(batch) {
  if (std::string why = device_fft_size_problem(size); !why.empty())
    throw std::runtime_error("device FFT: " + why);
  ARDCELL_CHECK(batch >= 1, "ClFft2d: batch must be at least 1");
  std::string error;
  kernels_ = OpenClKernels::create(ctx, &error);
  if (!kernels_) throw std::runtime_error(error.substr(0, error.find('\n')));
  for (int radix : {1, 2, 3, 4, 5, 7, 8, 16}) {
    pass_[radix] = kernels_->kernel(("fft_pass_radix" + std::to_string(radix)).c_str());
    complex_pass_[radix] =
        kernels_->kernel(("fft_complex_pass_radix" + std::to_string(radix)).c_str());
    // The passes launch work-groups of kGroupColumns x kGroupRows: a device that cannot run
    // them refuses here, where the engine falls back to the CPU with one line, not mid-frame.
    for (cl_kernel k : {pass_[radix], complex_pass_[radix]}) {
      std::size_t largest = 0;
      opencl_check(clGetKernelWorkGroupInfo(k, ctx.device().device, CL_KERNEL_WORK_GROUP_SIZE,
                                            sizeof largest, &largest, nullptr),
                   "clGetKernelWorkGroupInfo");
      if (largest < kGroupColumns * kGroupRows)
        throw std::runtime_error("device FFT: work-groups of " +
                                 std::to_string(kGroupColumns * kGroupRows) +
                                 " work-items, the device runs at most " + std::to_string(largest));
    }
  }
  const int nx = size.x, ny = size.y, w = width();
  // An even nx transforms each real row as a complex row of nx / 2 (fft.cl: the split, merge).
  half_ = nx % 2 == 0 ? nx / 2 : 0;
  rows_.n = half_ > 0 ? half_ : nx;
  rows_.radices = fft_radices(rows_.n);
  rows_.roots = upload_roots(ctx, rows_.n);
  split_roots_ = upload_roots(ctx, nx);
  rows_.per_field = ny;
  columns_.n = ny;
  columns_.radices = fft_radices(ny);
  columns_.roots = upload_roots(ctx, ny);
  columns_.per_field = w;
  columns_.transforms_fastest = true;
  const std::size_t complex_rows =
      std::size_t(batch) * std::size_t(ny) * std::size_t(std::max(rows_.n, w)) * 2 * sizeof(float);
  rows_a_ = ctx.allocate(complex_rows);
  rows_b_ = ctx.allocate(complex_rows);
}

OpenClBuffer ClFft2d::allocate_real() const {
  return ctx_.allocate(std::size_t(batch_) * std::size_t(cells()) * sizeof(float));
}

OpenClBuffer ClFft2d::allocate_spectrum() const {
  return ctx_.allocate(std::size_t(batch_) * std::size_t(modes()) * 2 * sizeof(float));
}

void ClFft2d::run(const Dimension& d, bool inverse, const OpenClBuffer& in, const Layout& in_layout,
                  const OpenClBuffer& out, const Layout& out_layout,
                  const OpenClBuffer* const scratch[2], const Layout& between) {
  const int passes = int(d.radices.size());
  int span = 1;
  const OpenClBuffer* from = &in;
  const Layout* from_layout = &in_layout;
  for (int p = 0; p < passes; ++p) {
    const int radix = d.radices[std::size_t(p)];
    const bool last = p == passes - 1;
    const OpenClBuffer* to = last ? &out : scratch[p % 2];
    const Layout& a = *from_layout;
    const Layout& b = last ? out_layout : between;
    cl_kernel k = a.kind == 0 && b.kind == 0 ? complex_pass_[radix] : pass_[radix];
    set_kernel_args(k, *from, *to, d.roots, split_roots_, d.n, half_, span, d.n / (span * radix),
                    int(inverse), d.per_field, int(d.transforms_fastest), a.kind, a.stride,
                    a.distance, a.field_distance, b.kind, b.stride, b.distance, b.field_distance,
                    b.keep);
    // One work-group shape for every pass, 16 along dimension 0 (16 neighbouring columns, or j
    // of a row): PoCL compiles a kernel once per shape, and a shape fitted to each extent
    // doubled the compiling on a cold cache for about 5% less time a transform.
    const std::size_t per_transform = std::size_t(d.n / radix);
    const std::size_t extent[2] = {d.transforms_fastest ? std::size_t(d.per_field) : per_transform,
                                   d.transforms_fastest ? per_transform : std::size_t(d.per_field)};
    const std::size_t local[3] = {kGroupColumns, kGroupRows, 1};
    const std::size_t global[3] = {(extent[0] + local[0] - 1) / local[0] * local[0],
                                   (extent[1] + local[1] - 1) / local[1] * local[1],
                                   std::size_t(batch_)};
    opencl_check(
        clEnqueueNDRangeKernel(ctx_.queue(), k, 3, nullptr, global, local, 0, nullptr, nullptr),
        "clEnqueueNDRangeKernel");
    span *= radix;
    from = to;
    from_layout = &between;
  }
}

// The layouts of the passes' buffers (fft.cl's kinds): the real rows (an even nx's read and
// written as complex rows of half its length; an odd one's read as reals, written as real
// parts), the complex rows between row passes, what the forward row passes leave (an even nx's
// complex rows Z, an odd one's half spectrum), the half spectrum's columns, and how the first
// pass of each phase reads what the other phase left.
struct ClFft2d::Layouts {
  Layout real_rows, complex_rows, row_output, half_columns, column_input, row_input;
};

ClFft2d::Layouts ClFft2d::layouts() const {
  const int nx = size_.x, ny = size_.y, w = width(), m = rows_.n;
  Layouts l;
  l.half_columns = {0, w, 1, w * ny, ny};
  if (half_ > 0) {
    l.real_rows = l.complex_rows = l.row_output = {0, 1, m, m * ny, m};
    l.column_input = {3, m, 1, m * ny, ny};  // the split, from the rows' Z
    l.row_input = {4, 1, w, w * ny, w};      // the merge, from the half spectrum's rows
  } else {
    l.real_rows = {1, 1, nx, nx * ny, nx};
    l.complex_rows = {0, 1, nx, nx * ny, nx};
    l.row_output = {0, 1, w, w * ny, w};  // the half spectrum's first nx / 2 + 1 columns
    l.column_input = l.half_columns;      // the row passes kept the half spectrum's columns
    l.row_input = {2, 1, w, w * ny, w};   // each row rebuilt from its Hermitian half
  }
  return l;
}

// The buffers each pass reads and writes, so that no pass reads the buffer it writes: the row
// passes ping-pong between rows_a_ and rows_b_; the column passes start from the spectrum when
// they are two or more (their scratch the rows buffers), else from the rows buffer the last row
// pass did not read.
void ClFft2d::forward(const OpenClBuffer& real, const OpenClBuffer& spectrum) {
  const Layouts l = layouts();
  const OpenClBuffer* const a_then_b[2] = {&rows_a_, &rows_b_};
  const OpenClBuffer* const b_then_a[2] = {&rows_b_, &rows_a_};
  const int row_passes = int(rows_.radices.size());
  // The buffer the last row pass reads (real when it is the first).
  const OpenClBuffer* last_row_input = row_passes == 1 ? &real : a_then_b[(row_passes - 2) % 2];
  const OpenClBuffer& column_input = columns_.radices.size() >= 2 ? spectrum
                                     : last_row_input == &rows_a_ ? rows_b_
                                                                  : rows_a_;
  run(rows_, false, real, l.real_rows, column_input, l.row_output, a_then_b, l.complex_rows);
  run(columns_, false, column_input, l.column_input, spectrum, l.half_columns,
      &column_input == &rows_a_ ? b_then_a : a_then_b, l.half_columns);
}

void ClFft2d::backward(const OpenClBuffer& spectrum, const OpenClBuffer& real) {
  const Layouts l = layouts();
  const OpenClBuffer* const a_then_b[2] = {&rows_a_, &rows_b_};
  const OpenClBuffer* const b_then_a[2] = {&rows_b_, &rows_a_};
  // Two or more column passes end back in the spectrum (pass 0 reads it, the last writes it).
  const OpenClBuffer& column_output = columns_.radices.size() >= 2 ? spectrum : rows_a_;
  run(columns_, true, spectrum, l.half_columns, column_output, l.half_columns, a_then_b,
      l.half_columns);
  run(rows_, true, column_output, l.row_input, real, l.real_rows,
      &column_output == &rows_a_ ? b_then_a : a_then_b, l.complex_rows);
}

// --- launches shared by the twins ----------------------------------------------------------------

namespace {

// Field `at` of the packed batch `packed` <- f's interior, and back.
void pack(OpenClKernels& cl, cl_kernel k, const DeviceField& f, const OpenClBuffer& packed,
          int at) {
  set_kernel_args(k, f.buffer, f.stride, f.origin, f.size.x, f.size.y, packed, at);
  cl.enqueue_cells(k, f.interior());
}

void unpack(OpenClKernels& cl, cl_kernel k, const OpenClBuffer& packed, int at, DeviceField& f) {
  set_kernel_args(k, packed, at, f.size.x, f.size.y, f.buffer, f.stride, f.origin);
  cl.enqueue_cells(k, f.interior());
}

}  // namespace

// --- OpenClPeriodicSolve ---------------------------------------------------------------------

OpenClPeriodicSolve::OpenClPeriodicSolve(OpenClKernels& cl, ClFft2d& fft)
    : cl_(cl),
      fft_(fft),
      real_(fft.allocate_real()),
      spectrum_(fft.allocate_spectrum()),
      multipliers_(fft.allocate_spectrum()),
      staging_(std::size_t(fft.modes()) * 2),
      pack_(cl.kernel("spectral_pack")),
      unpack_(cl.kernel("spectral_unpack")),
      multiply_(cl.kernel("spectral_multiply")) {
  ARDCELL_CHECK(fft.batch() == 1, "OpenClPeriodicSolve: the transforms must have batch 1");
}

void OpenClPeriodicSolve::upload(const PeriodicStencilSolve& solve) {
  const int w = fft_.width(), ny = fft_.size().y;
  for (int my = 0; my < ny; ++my)
    for (int mx = 0; mx < w; ++mx) {
      const std::complex<float> m = solve.applied_multiplier(mx, my);
      const std::size_t i = (std::size_t(my) * std::size_t(w) + std::size_t(mx)) * 2;
      staging_[i] = m.real();
      staging_[i + 1] = m.imag();
    }
  cl_.context().write(multipliers_, staging_.data(), staging_.size() * sizeof(float));
  delta_ = solve.delta();
  stencil_ = solve.stencil();
  uploaded_ = true;
}

void OpenClPeriodicSolve::solve(const PeriodicStencilSolve& solve, DeviceField& x) {
  ARDCELL_CHECK(solve.size() == fft_.size() && x.size == fft_.size(),
                "OpenClPeriodicSolve: the field, the solve and the transforms differ in size");
  if (!uploaded_ || solve.delta() != delta_ ||
      !std::equal(std::begin(stencil_.w), std::end(stencil_.w), std::begin(solve.stencil().w)))
    upload(solve);
  pack(cl_, pack_, x, real_, 0);
  fft_.forward(real_, spectrum_);
  set_kernel_args(multiply_, spectrum_, multipliers_, fft_.modes());
  cl_.enqueue_items(multiply_, fft_.modes());
  fft_.backward(spectrum_, real_);
  unpack(cl_, unpack_, real_, 0, x);
}

// --- OpenClEtdrk4 ----------------------------------------------------------------------------

namespace {
constexpr int kEtdTables = 6;  // E, E2, Q, f1, f2, f3 (spectral.cl's etd_coefficient)
}

OpenClEtdrk4::OpenClEtdrk4(OpenClKernels& cl, ClFft2d& fft)
    : cl_(cl),
      fft_(fft),
      u_real_(fft.allocate_real()),
      n_real_(fft.allocate_real()),
      v_(fft.allocate_spectrum()),
      n_u_(fft.allocate_spectrum()),
      n_ab_(fft.allocate_spectrum()),
      n_stage_(fft.allocate_spectrum()),
      next_(fft.allocate_spectrum()),
      coefficients_(cl.context().allocate(std::size_t(2 * kEtdTables) * std::size_t(fft.modes()) *
                                          sizeof(float))),
      staging_(std::size_t(2 * kEtdTables) * std::size_t(fft.modes())),
      pack_(cl.kernel("spectral_pack")),
      unpack_(cl.kernel("spectral_unpack")),
      reaction_(cl.kernel("spectral_reaction")),
      combine_(cl.kernel("etdrk4_combine")) {
  ARDCELL_CHECK(fft.batch() == 2, "OpenClEtdrk4: the transforms must have batch 2 (A and B)");
}

void OpenClEtdrk4::upload(const PeriodicEtdrk4& etdrk4) {
  const int w = fft_.width(), ny = fft_.size().y;
  const std::size_t modes = std::size_t(fft_.modes());
  for (int c = 0; c < 2; ++c)
    for (int my = 0; my < ny; ++my)
      for (int mx = 0; mx < w; ++mx) {
        const PeriodicEtdrk4::ModeCoefficients k = etdrk4.coefficients(c, mx, my);
        const float tables[kEtdTables] = {k.e, k.e2, k.q, k.f1, k.f2, k.f3};
        const std::size_t m = std::size_t(my) * std::size_t(w) + std::size_t(mx);
        for (int t = 0; t < kEtdTables; ++t)
          staging_[std::size_t(c * kEtdTables + t) * modes + m] = tables[t];
      }
  cl_.context().write(coefficients_, staging_.data(), staging_.size() * sizeof(float));
  dt_ = etdrk4.dt();
  rates_[0] = etdrk4.rate(0);
  rates_[1] = etdrk4.rate(1);
  uploaded_ = true;
}

void OpenClEtdrk4::reaction(const ReactionParams* params) {
  float q[5] = {0, 0, 0, 0, 0};
  if (params) cl_reaction_args(*params, q);
  set_kernel_args(reaction_, u_real_, n_real_, fft_.cells(), params ? int(params->model) : 0, q[0],
                  q[1], q[2], q[3], q[4], int(params != nullptr));
  cl_.enqueue_items(reaction_, fft_.cells());
}

void OpenClEtdrk4::combine(int stage) {
  const float scale = float(1.0 / (double(fft_.size().x) * double(fft_.size().y)));
  set_kernel_args(combine_, v_, n_u_, n_ab_, n_stage_, next_, coefficients_, fft_.modes(), stage,
                  scale);
  cl_.enqueue_items(combine_, 2 * fft_.modes());
  fft_.backward(next_, u_real_);
}

// PeriodicEtdrk4::step's passes on whole spectra: each stage's field back in cells (u_real_)
// for its reaction, each stage's combination per mode (spectral.cl's etdrk4_combine).
void OpenClEtdrk4::step(const PeriodicEtdrk4& etdrk4, DeviceField& a, DeviceField& b,
                        const ReactionParams* reaction_params) {
  ARDCELL_CHECK(etdrk4.size() == fft_.size() && a.size == fft_.size() && b.size == fft_.size(),
                "OpenClEtdrk4: the fields, the step and the transforms differ in size");
  if (!uploaded_ || etdrk4.dt() != dt_ || etdrk4.rate(0) != rates_[0] ||
      etdrk4.rate(1) != rates_[1])
    upload(etdrk4);
  pack(cl_, pack_, a, u_real_, 0);
  pack(cl_, pack_, b, u_real_, 1);
  // N(u) from u in cells (forward keeps its input, so the order is free).
  reaction(reaction_params);
  fft_.forward(u_real_, v_);
  fft_.forward(n_real_, n_stage_);
  combine(0);                                 // a
  for (int stage = 1; stage <= 3; ++stage) {  // N_a -> b, N_b -> c, N_c -> the new u
    reaction(reaction_params);
    fft_.forward(n_real_, n_stage_);
    combine(stage);
  }
  unpack(cl_, unpack_, u_real_, 0, a);
  unpack(cl_, unpack_, u_real_, 1, b);
}

}  // namespace ardcell
#endif
