#if defined(ARDCELL_WITH_OPENCL)
#include "kernels/cl/opencl_fft.h"

#include <clFFT.h>

#include <algorithm>
#include <atomic>
#include <complex>
#include <cstdio>
#include <iterator>
#include <stdexcept>
#include <type_traits>

#include "runtime/check.h"

namespace ardcell {

namespace {

// clFFT's library state: clfftSetup before the first plan, clfftTeardown when the process exits
// (it releases every plan, program and kernel clFFT still holds; the kernel signatures it keeps
// past that, runtime/opencl/opencl_context.cpp has LeakSanitizer suppress).
std::atomic<bool> g_clfft_torn_down{false};

struct ClfftLibrary {
  ClfftLibrary() {
    clfftSetupData setup;
    clfftInitSetupData(&setup);
    status = clfftSetup(&setup);
  }
  ~ClfftLibrary() {
    if (status == CLFFT_SUCCESS) clfftTeardown();
    g_clfft_torn_down = true;
  }
  clfftStatus status = CLFFT_SUCCESS;
};

void clfft_check(clfftStatus status, const char* what) {
  if (status == CLFFT_SUCCESS) return;
  char line[160];
  std::snprintf(line, sizeof line, "clFFT: %s failed (status %d)", what, int(status));
  throw std::runtime_error(line);
}

void setup_clfft_once() {
  static ClfftLibrary library;  // thread-safe initialisation; destroyed at exit
  clfft_check(library.status, "clfftSetup");
}

// The largest prime factor of n (n >= 1).
int largest_prime_factor(int n) {
  int largest = 1;
  for (int p = 2; p * p <= n; ++p)
    while (n % p == 0) largest = p, n /= p;
  return std::max(largest, n);
}

}  // namespace

// The header keeps plan handles as std::size_t, without clFFT.h.
static_assert(std::is_same_v<clfftPlanHandle, std::size_t>);

std::string clfft_size_problem(Int2 size) {
  // clFFT 2.12 has radices 2, 3, 5, 7, 11 and 13.
  for (int n : {size.x, size.y}) {
    const int p = largest_prime_factor(n);
    if (p > 13) {
      char line[96];
      std::snprintf(line, sizeof line, "%d has a prime factor clFFT lacks (%d)", n, p);
      return line;
    }
  }
  return "";
}

// --- ClFft2d -----------------------------------------------------------------------------------

ClFft2d::ClFft2d(OpenClContext& ctx, Int2 size, int batch) : ctx_(ctx), size_(size), batch_(batch) {
  if (std::string why = clfft_size_problem(size); !why.empty())
    throw std::runtime_error("clFFT: " + why);
  setup_clfft_once();
  const std::size_t nx = std::size_t(size.x), ny = std::size_t(size.y), w = std::size_t(width());
  std::size_t lengths[2] = {nx, ny};
  std::size_t real_strides[2] = {1, nx};
  std::size_t spectral_strides[2] = {1, w};
  std::size_t scratch = 0;
  cl_command_queue queue = ctx.queue();
  try {
    for (bool forward : {true, false}) {
      clfftPlanHandle& plan = forward ? forward_plan_ : backward_plan_;
      clfft_check(clfftCreateDefaultPlan(&plan, ctx.context(), CLFFT_2D, lengths),
                  "clfftCreateDefaultPlan");
      made_plans_ += 1;
      clfft_check(clfftSetPlanPrecision(plan, CLFFT_SINGLE), "clfftSetPlanPrecision");
      clfft_check(forward ? clfftSetLayout(plan, CLFFT_REAL, CLFFT_HERMITIAN_INTERLEAVED)
                          : clfftSetLayout(plan, CLFFT_HERMITIAN_INTERLEAVED, CLFFT_REAL),
                  "clfftSetLayout");
      clfft_check(clfftSetResultLocation(plan, CLFFT_OUTOFPLACE), "clfftSetResultLocation");
      clfft_check(clfftSetPlanInStride(plan, CLFFT_2D, forward ? real_strides : spectral_strides),
                  "clfftSetPlanInStride");
      clfft_check(clfftSetPlanOutStride(plan, CLFFT_2D, forward ? spectral_strides : real_strides),
                  "clfftSetPlanOutStride");
      clfft_check(forward ? clfftSetPlanDistance(plan, nx * ny, w * ny)
                          : clfftSetPlanDistance(plan, w * ny, nx * ny),
                  "clfftSetPlanDistance");
      clfft_check(clfftSetPlanBatchSize(plan, std::size_t(batch)), "clfftSetPlanBatchSize");
      // The CPU's tables fold in 1 / (nx ny): the way back is the plain sum.
      if (!forward) clfft_check(clfftSetPlanScale(plan, CLFFT_BACKWARD, 1.0f), "clfftSetPlanScale");
      clfft_check(clfftBakePlan(plan, 1, &queue, nullptr, nullptr), "clfftBakePlan");
      std::size_t bytes = 0;
      clfft_check(clfftGetTmpBufSize(plan, &bytes), "clfftGetTmpBufSize");
      scratch = std::max(scratch, bytes);
    }
    // One temporary buffer for both plans (they run in queue order), ours: clFFT would
    // otherwise allocate one of its own on the first transform.
    if (scratch > 0) scratch_ = ctx.allocate(scratch);
  } catch (...) {
    destroy_plans();
    throw;
  }
}

ClFft2d::~ClFft2d() { destroy_plans(); }

void ClFft2d::destroy_plans() {
  // After clfftTeardown (an object that outlives main's) the plans are released already.
  if (!g_clfft_torn_down) {
    if (made_plans_ > 0) clfftDestroyPlan(&forward_plan_);
    if (made_plans_ > 1) clfftDestroyPlan(&backward_plan_);
  }
  made_plans_ = 0;
}

OpenClBuffer ClFft2d::allocate_real() const {
  return ctx_.allocate(std::size_t(batch_) * std::size_t(cells()) * sizeof(float));
}

OpenClBuffer ClFft2d::allocate_spectrum() const {
  return ctx_.allocate(std::size_t(batch_) * std::size_t(modes()) * 2 * sizeof(float));
}

void ClFft2d::enqueue(std::size_t plan, int direction, const OpenClBuffer& in,
                      const OpenClBuffer& out) {
  cl_command_queue queue = ctx_.queue();
  cl_mem input = in.get(), output = out.get();
  clfft_check(clfftEnqueueTransform(plan, clfftDirection(direction), 1, &queue, 0, nullptr, nullptr,
                                    &input, &output, scratch_ ? scratch_.get() : nullptr),
              "clfftEnqueueTransform");
}

void ClFft2d::forward(const OpenClBuffer& real, const OpenClBuffer& spectrum) {
  enqueue(forward_plan_, CLFFT_FORWARD, real, spectrum);
}

void ClFft2d::backward(const OpenClBuffer& spectrum, const OpenClBuffer& real) {
  enqueue(backward_plan_, CLFFT_BACKWARD, spectrum, real);
}

// --- launches shared by the twins ----------------------------------------------------------------

namespace {

void enqueue_1d(OpenClKernels& cl, cl_kernel k, int items) {
  // A fixed work-group size (PoCL compiles each kernel once per work-group size).
  constexpr std::size_t kGroup = 64;
  cl.context().enqueue(k, (std::size_t(items) + kGroup - 1) / kGroup * kGroup, kGroup);
}

// Field `at` of the packed batch `packed` <- f's interior, and back.
void pack(OpenClKernels& cl, const DeviceField& f, const OpenClBuffer& packed, int at) {
  cl_kernel k = cl.kernel("spectral_pack");
  set_kernel_args(k, f.buffer, f.stride, f.origin, f.size.x, f.size.y, packed, at);
  cl.enqueue_cells(k, f.interior());
}

void unpack(OpenClKernels& cl, const OpenClBuffer& packed, int at, DeviceField& f) {
  cl_kernel k = cl.kernel("spectral_unpack");
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
      staging_(std::size_t(fft.modes()) * 2) {
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
  pack(cl_, x, real_, 0);
  fft_.forward(real_, spectrum_);
  cl_kernel k = cl_.kernel("spectral_multiply");
  set_kernel_args(k, spectrum_, multipliers_, fft_.modes());
  enqueue_1d(cl_, k, fft_.modes());
  fft_.backward(spectrum_, real_);
  unpack(cl_, real_, 0, x);
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
      staging_(std::size_t(2 * kEtdTables) * std::size_t(fft.modes())) {
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
  cl_kernel k = cl_.kernel("spectral_reaction");
  set_kernel_args(k, u_real_, n_real_, fft_.cells(), params ? int(params->model) : 0, q[0], q[1],
                  q[2], q[3], q[4], int(params != nullptr));
  enqueue_1d(cl_, k, fft_.cells());
}

void OpenClEtdrk4::combine(int stage) {
  const float scale = float(1.0 / (double(fft_.size().x) * double(fft_.size().y)));
  cl_kernel k = cl_.kernel("etdrk4_combine");
  set_kernel_args(k, v_, n_u_, n_ab_, n_stage_, next_, coefficients_, fft_.modes(), stage, scale);
  enqueue_1d(cl_, k, 2 * fft_.modes());
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
  pack(cl_, a, u_real_, 0);
  pack(cl_, b, u_real_, 1);
  // N(u) before u's transform: clFFT may use a real-to-complex transform's input as scratch.
  reaction(reaction_params);
  fft_.forward(u_real_, v_);
  fft_.forward(n_real_, n_stage_);
  combine(0);                                 // a
  for (int stage = 1; stage <= 3; ++stage) {  // N_a -> b, N_b -> c, N_c -> the new u
    reaction(reaction_params);
    fft_.forward(n_real_, n_stage_);
    combine(stage);
  }
  unpack(cl_, u_real_, 0, a);
  unpack(cl_, u_real_, 1, b);
}

}  // namespace ardcell
#endif
