// Table 1 (seed 000, section 7.2) on the OpenCL back end: Table1/opencl-stream/... and
// Table1/opencl-blocked/..., beside the CPU rows of bench/table1_bench.cpp, with the same
// naming: Table1/<backend>-<schedule>/<fluid|ard>/<N>. One iteration is one whole frame, enqueued
// and finished (as a frame must be before it is shown). Counters: fps, bytes_per_s (the
// sweep-by-sweep minimum traffic of host/table1.h, so GPU figures compare with the device's
// bandwidth).
//
// The device: ARDCELL_CL_DEVICE=N (as `--cl-device N`, see `ardcell devices`), else the first
// GPU, else the first device. Without OpenCL the rows report an error and the program exits 0.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "host/table1_opencl.h"

namespace ardcell {
namespace {

struct Device {
  std::unique_ptr<OpenClContext> ctx;
  std::unique_ptr<OpenClKernels> cl;
  std::string error;
};

Device& device() {
  static Device d = [] {
    Device dev;
    const char* env = std::getenv("ARDCELL_CL_DEVICE");
    const int index = env ? std::atoi(env) : -1;
    dev.ctx = OpenClContext::open(index, &dev.error);
    if (dev.ctx) dev.cl = OpenClKernels::create(*dev.ctx, &dev.error);
    return dev;
  }();
  return d;
}

void run_table1(benchmark::State& state, ClSchedule schedule, bool rd, int n) {
  Device& d = device();
  if (!d.cl) {
    state.SkipWithError(("no OpenCL: " + d.error).c_str());
    return;
  }
  Table1Options o;
  o.n = n;
  o.rd = rd;
  o.schedule = Table1Schedule::kSerial;
  const Table1Workload initial(o);  // initial conditions only; never stepped
  OpenClStamFrame frame(*d.cl, table1_cl_params({n, n}, rd), schedule);
  table1_cl_upload(initial, frame);
  frame.step();  // warm-up: first launches compile the work-group functions on some drivers
  frame.finish();
  for (auto _ : state) {
    frame.step();
    frame.finish();
  }
  const double frames = double(state.iterations());
  state.counters["fps"] = benchmark::Counter(frames, benchmark::Counter::kIsRate);
  state.counters["bytes_per_s"] =
      benchmark::Counter(frames * initial.bytes_per_frame(), benchmark::Counter::kIsRate);
  state.SetLabel(d.ctx->device().device_name);
}

// Sizes as bench/table1_bench.cpp takes them: ARDCELL_BENCH_SIZES="512,1024" (default 256, 512,
// 1024; add 4096 on a GPU).
std::vector<int> sizes_from_env() {
  std::vector<int> sizes{256, 512, 1024};
  if (const char* s = std::getenv("ARDCELL_BENCH_SIZES")) {
    sizes.clear();
    std::stringstream in(s);
    std::string item;
    while (std::getline(in, item, ','))
      if (!item.empty()) sizes.push_back(std::atoi(item.c_str()));
  }
  return sizes;
}

// Names exactly as bench/table1_bench.cpp's: Table1/<schedule>/<fluid|ard>/<N>, the schedule
// being opencl-stream or opencl-blocked, so `ardcell bench table1` can merge the rows.
void register_all() {
  for (auto [name, schedule] :
       {std::pair{"stream", ClSchedule::kStream}, std::pair{"blocked", ClSchedule::kBlocked}})
    for (bool rd : {false, true})
      for (int n : sizes_from_env()) {
        const std::string full =
            std::string("Table1/opencl-") + name + (rd ? "/ard/" : "/fluid/") + std::to_string(n);
        benchmark::RegisterBenchmark(
            full.c_str(),
            [schedule, rd, n](benchmark::State& s) { run_table1(s, schedule, rd, n); })
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
      }
}

}  // namespace
}  // namespace ardcell

int main(int argc, char** argv) {
  ardcell::register_all();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
