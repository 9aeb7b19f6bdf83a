#pragma once
// Environment knobs shared by the benchmark programs.
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "drivers/bench_program.h"
#include "runtime/opencl/backend_choice.h"  // OpenClContext (empty without OpenCL)
#if defined(ARDCELL_WITH_OPENCL)
#include "kernels/cl/opencl_kernels.h"
#include "runtime/opencl/opencl_context.h"
#endif

namespace ardcell {

// The environment variable `name` when set and not empty, else `fallback`.
inline std::string bench_env_text(const char* name, const char* fallback) {
  const char* s = std::getenv(name);
  return s && *s ? s : fallback;
}
inline int bench_env_int(const char* name, int fallback) {
  const char* s = std::getenv(name);
  return s && *s ? std::atoi(s) : fallback;
}

// Grid sizes from ARDCELL_BENCH_SIZES="512,1024", else `defaults`.
inline std::vector<int> bench_sizes_from_env(std::vector<int> defaults) {
  const char* s = std::getenv("ARDCELL_BENCH_SIZES");
  if (!s) return defaults;
  std::vector<int> sizes;
  for (const std::string& item : split_commas(s)) sizes.push_back(std::atoi(item.c_str()));
  return sizes;
}

// The OpenCL device of a benchmark program's run, its kernels built: ARDCELL_CL_DEVICE=N picks it
// (as --cl-device N; default the first), ARDCELL_CL_DEVICE=none leaves it out. Null when there is
// none; then `program` says why once on stderr and the program registers no opencl rows.
inline OpenClContext* bench_opencl(const char* program) {
#if defined(ARDCELL_WITH_OPENCL)
  static std::unique_ptr<OpenClContext> ctx = [program] {
    const char* env = std::getenv("ARDCELL_CL_DEVICE");
    if (env && std::string(env) == "none") return std::unique_ptr<OpenClContext>();
    std::string error;
    auto c = OpenClContext::open(env ? std::atoi(env) : -1, &error);
    if (c && !OpenClKernels::prepare(*c, &error)) c.reset();
    if (!c) std::fprintf(stderr, "%s: no OpenCL rows: %s\n", program, error.c_str());
    return c;
  }();
  return ctx.get();
#else
  (void)program;
  return nullptr;
#endif
}

}  // namespace ardcell
