// `ardcell devices`: every OpenCL platform and device, numbered as `--cl-device N` takes them,
// with compute units, local memory and global memory.
#include <cstdint>
#include <string>

#include "drivers/cli.h"
#if defined(ARDCELL_WITH_OPENCL)
#include "runtime/opencl/opencl_context.h"
#endif

namespace ardcell {
namespace {

std::string bytes_text(std::uint64_t b) {
  char buf[64];
  if (b >= (std::uint64_t(1) << 30))
    std::snprintf(buf, sizeof buf, "%.1f GiB", double(b) / double(1 << 30));
  else if (b >= (std::uint64_t(1) << 20))
    std::snprintf(buf, sizeof buf, "%.1f MiB", double(b) / double(1 << 20));
  else
    std::snprintf(buf, sizeof buf, "%llu KiB", static_cast<unsigned long long>(b >> 10));
  return buf;
}

int list_devices(CliContext& ctx) {
#if defined(ARDCELL_WITH_OPENCL)
  std::string error;
  const std::vector<OpenClDeviceInfo> devices = list_opencl_devices(&error);
  if (devices.empty()) {
    std::fprintf(ctx.err, "ardcell devices: %s\n", error.c_str());
    return kExitFailure;
  }
  int platform = -1;
  for (const OpenClDeviceInfo& d : devices) {
    if (d.platform_index != platform) {
      platform = d.platform_index;
      std::fprintf(ctx.out, "platform %d: %s (%s)\n", platform, d.platform_name.c_str(),
                   d.platform_version.c_str());
    }
    std::fprintf(ctx.out,
                 "  device %d: %s [%s]  compute units %u, local memory %s (%s), global memory "
                 "%s, max work-group %zu, %s\n",
                 d.index, d.device_name.c_str(), d.type.c_str(), d.compute_units,
                 bytes_text(d.local_mem_bytes).c_str(),
                 d.local_mem_dedicated ? "on chip" : "emulated in global",
                 bytes_text(d.global_mem_bytes).c_str(), d.max_work_group_size,
                 d.device_version.c_str());
  }
  std::fprintf(ctx.out, "use one with --backend opencl --cl-device N\n");
  return kExitOk;
#else
  std::fprintf(ctx.err, "ardcell devices: this build has no OpenCL (ARDCELL_WITH_OPENCL=OFF)\n");
  return kExitFailure;
#endif
}

}  // namespace

void add_devices_command(CLI::App& app, CliContext& ctx) {
  CLI::App* cmd = app.add_subcommand(
      "devices", "List every OpenCL platform and device (the N of --cl-device N)");
  cmd->callback([&ctx] { ctx.exit_code = list_devices(ctx); });
}

}  // namespace ardcell
