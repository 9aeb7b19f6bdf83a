// OpenClDevice's ops of seed 003's generalized operator and of the second-order
// reaction-diffusion schemes (host/engine/device.h): the explicit step's and the tensor field's
// twins, the trapezoidal reaction and SBDF's right-hand side, and the periodic FFT steps (the
// semi-implicit solve of Eqn 28 and ETDRK4) by the device FFT (kernels/cl/opencl_fft.h), whose
// root tables and buffers are made on a size's first step and shared by the twins of that size;
// a size the device FFT cannot transform runs them on the CPU with one line. The tensor field's
// semi-implicit solve by the device BiCGSTAB (kernels/cl/opencl_tensor_field_solve.h) on the
// faces' resident copies; on a device without doubles on the CPU, with one line.
#if defined(ARDCELL_WITH_OPENCL)
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>

#include "host/engine/opencl_device.h"
#include "kernels/tensor_field_solve.h"

namespace ardcell {

const OpenClBuffer& OpenClDevice::stencil_weights(const GeneralizedTaps& k) {
  const auto same = [](const GeneralizedTaps& a, const GeneralizedTaps& b) {
    if (a.count != b.count) return false;
    for (int t = 0; t < a.count; ++t)
      if (a.taps[t].dx != b.taps[t].dx || a.taps[t].dy != b.taps[t].dy ||
          a.taps[t].weight != b.taps[t].weight)
        return false;
    return true;
  };
  for (StencilTwin& t : stencils_)
    if (t.host == &k) {
      if (!same(t.uploaded, k)) {
        t.weights = cl_->stencil_groups(k);
        t.uploaded = k;
      }
      return t.weights;
    }
  stencils_.push_back({&k, k, cl_->stencil_groups(k)});
  return stencils_.back().weights;
}

void OpenClDevice::generalized_rd(const FieldF& a, const FieldF& b, FieldF& a_out, FieldF& b_out,
                                  const GeneralizedTaps& k, const GeneralizedRdParams& p) {
  const OpenClBuffer& weights = stencil_weights(k);
  const DeviceField& da = in(a);
  const DeviceField& db = in(b);
  cl_->generalized_rd(da, db, out(a_out), out(b_out), weights, p);
}

void OpenClDevice::tensor_field_rd(const FieldF& a, const FieldF& b, FieldF& a_out, FieldF& b_out,
                                   const Rank2FaceField& d, const GeneralizedRdParams& p) {
  cl_->tensor_field_rd(in(a), in(b), out(a_out), out(b_out), in(d.x_xx), in(d.x_xy), in(d.y_xy),
                       in(d.y_yy), p);
}

ClFft2d& OpenClDevice::fft(Int2 size, int batch) {
  for (const std::unique_ptr<ClFft2d>& f : ffts_)
    if (f->size() == size && f->batch() == batch) return *f;
  ffts_.push_back(std::make_unique<ClFft2d>(ctx_, size, batch));
  return *ffts_.back();
}

template <class Cpu, class OnDevice>
OpenClDevice::FftTwin<Cpu, OnDevice>& OpenClDevice::fft_twin(
    std::deque<FftTwin<Cpu, OnDevice>>& twins, const Cpu& cpu, int batch) {
  for (FftTwin<Cpu, OnDevice>& t : twins)
    if (t.cpu == &cpu && t.size == cpu.size()) return t;
  FftTwin<Cpu, OnDevice> t{&cpu, cpu.size(), nullptr, device_fft_size_problem(cpu.size())};
  if (t.why_not.empty()) {
    try {
      t.device = std::make_unique<OnDevice>(*cl_, fft(t.size, batch));
    } catch (const std::runtime_error& e) {  // no device FFT: the CPU's op instead
      t.why_not = e.what();
    }
  }
  // An op made anew at a freed one's address replaces its twin.
  for (FftTwin<Cpu, OnDevice>& old : twins)
    if (old.cpu == &cpu) return old = std::move(t);
  twins.push_back(std::move(t));
  return twins.back();
}

void OpenClDevice::periodic_solve(PeriodicStencilSolve& solve_a, FieldF& a,
                                  PeriodicStencilSolve& solve_b, FieldF& b) {
  // Twins live in a deque: making b's keeps a reference to a's valid.
  PeriodicSolveTwin& twin_a = fft_twin(periodic_twins_, solve_a, 1);
  PeriodicSolveTwin& twin_b = fft_twin(periodic_twins_, solve_b, 1);
  if (twin_a.device && twin_b.device) {
    twin_a.device->solve(solve_a, out(a));
    twin_b.device->solve(solve_b, out(b));
    return;
  }
  say_fallback(DeviceOp::kPeriodicSolve, "rd.scheme implicit or semi-implicit",
               (twin_a.device ? twin_b : twin_a).why_not.c_str());
  host_in(a);
  host_in(b);
  cpu_.periodic_solve(solve_a, a, solve_b, b);
  host_wrote(a);
  host_wrote(b);
}

SolveReport OpenClDevice::tensor_field_solve(TensorFieldSolve& solve, FieldF& x, double s) {
  if (cl_->has_fp64()) {
    TensorSolveTwin* twin = nullptr;
    for (TensorSolveTwin& t : tensor_solves_)
      if (t.cpu == &solve) twin = &t;
    if (!twin) twin = &tensor_solves_.emplace_back(TensorSolveTwin{&solve, nullptr});
    // An op made anew at a freed one's address (or of another size) replaces its twin.
    if (!twin->device || twin->device->size() != solve.size())
      twin->device = std::make_unique<OpenClTensorFieldSolve>(*cl_, solve.size());
    const Rank2FaceField& d = solve.faces();
    const ClRank2Faces faces{&in(d.x_xx), &in(d.x_xy), &in(d.y_xy), &in(d.y_yy)};
    return twin->device->solve(faces, out(x), s, solve.max_iterations(), solve.tolerance());
  }
  say_fallback(DeviceOp::kTensorFieldSolve,
               "rd.generalized.field, rd.scheme implicit or semi-implicit",
               "the device has no doubles (cl_khr_fp64)");
  host_in(x);
  const SolveReport r = cpu_.tensor_field_solve(solve, x, s);
  host_wrote(x);
  return r;
}

void OpenClDevice::reaction_trapezoidal(FieldF& a, FieldF& b, const ReactionParams& p, float dt) {
  DeviceField& da = out(a);
  DeviceField& db = out(b);
  cl_->reaction_trapezoidal(da, db, da, db, box_of_size(a.size()), p, dt);
}

void OpenClDevice::sbdf_rhs(FieldF& a, FieldF& b, FieldF& a_prev, FieldF& b_prev,
                            const SbdfRhsParams& p) {
  DeviceField& da = out(a);
  DeviceField& db = out(b);
  DeviceField& dap = out(a_prev);
  DeviceField& dbp = out(b_prev);
  cl_->sbdf_rhs(da, db, dap, dbp, box_of_size(a.size()), p);
}

void OpenClDevice::etdrk4_step(PeriodicEtdrk4& etdrk4, FieldF& a, FieldF& b,
                               const ReactionParams* reaction) {
  Etdrk4Twin& twin = fft_twin(etdrk4_twins_, etdrk4, 2);
  if (twin.device) {
    DeviceField& da = out(a);
    twin.device->step(etdrk4, da, out(b), reaction);
    return;
  }
  say_fallback(DeviceOp::kEtdrk4, "rd.scheme etdrk4", twin.why_not.c_str());
  host_in(a);
  host_in(b);
  cpu_.etdrk4_step(etdrk4, a, b, reaction);
  host_wrote(a);
  host_wrote(b);
}

}  // namespace ardcell
#endif
