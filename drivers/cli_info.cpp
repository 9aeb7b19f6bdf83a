// `ardcell info`: version, build options, CPU features and cores.
#include <sched.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "drivers/chart.h"
#include "drivers/cli.h"
#ifdef ARDCELL_WITH_SDL2
#include "drivers/glyph_atlas_sdl.h"
#endif
#include "host/scenes/preset.h"

namespace ardcell {
namespace {

#if defined(ARDCELL_CHECKS) && ARDCELL_CHECKS
constexpr bool ARDCELL_CHECKS_ON = true;
#else
constexpr bool ARDCELL_CHECKS_ON = false;
#endif

const char* on_off(bool b) { return b ? "on" : "off"; }

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) {
      const std::size_t colon = line.find(':');
      if (colon != std::string::npos) return line.substr(colon + 2);
    }
  return "unknown";
}

std::string cpu_features() {
  std::string out;
#if defined(__x86_64__) || defined(__i386__)
  __builtin_cpu_init();
  auto add = [&](const char* name, bool have) {
    if (have) out += (out.empty() ? "" : " ") + std::string(name);
  };
  add("sse4.2", __builtin_cpu_supports("sse4.2"));
  add("avx", __builtin_cpu_supports("avx"));
  add("avx2", __builtin_cpu_supports("avx2"));
  add("fma", __builtin_cpu_supports("fma"));
  add("avx512f", __builtin_cpu_supports("avx512f"));
  if (out.empty()) out = "(none of sse4.2 avx avx2 fma avx512f)";
#else
  out = "(not an x86 CPU)";
#endif
  return out;
}

std::string compiled_for() {
  std::string out;
  [[maybe_unused]] auto add = [&](const char* name) {
    out += (out.empty() ? "" : " ") + std::string(name);
  };
#ifdef __SSE4_2__
  add("sse4.2");
#endif
#ifdef __AVX__
  add("avx");
#endif
#ifdef __AVX2__
  add("avx2");
#endif
#ifdef __FMA__
  add("fma");
#endif
#ifdef __AVX512F__
  add("avx512f");
#endif
#ifdef __ARM_NEON
  add("neon");
#endif
  return out.empty() ? "baseline" : out;
}

bool sanitized() {
#if defined(__SANITIZE_ADDRESS__)
  return true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
  return true;
#endif
#endif
  return false;
}

int do_info(CliContext& ctx) {
  FILE* o = ctx.out;
  std::fprintf(o, "ardcell %s\n", ARDCELL_VERSION);
#ifdef NDEBUG
  const char* build = "optimised (NDEBUG)";
#else
  const char* build = "debug assertions on";
#endif
  std::fprintf(o, "build: %s, %s, sanitizers %s, compiler %s\n", build,
               ARDCELL_CHECKS_ON ? "ARDCELL_DCHECK on" : "ARDCELL_DCHECK off",
               sanitized() ? "address+undefined" : "off", __VERSION__);
  std::fprintf(o,
               "options: opencl=%s hidapi=%s gpiod=%s sdl2=%s liblo=%s systemd=%s plplot=%s "
               "mpi=%s\n",
#ifdef ARDCELL_WITH_OPENCL
               on_off(true),
#else
               on_off(false),
#endif
#ifdef ARDCELL_WITH_HIDAPI
               on_off(true),
#else
               on_off(false),
#endif
#ifdef ARDCELL_WITH_GPIOD
               on_off(true),
#else
               on_off(false),
#endif
#ifdef ARDCELL_WITH_SDL2
               on_off(true),
#else
               on_off(false),
#endif
#ifdef ARDCELL_WITH_LIBLO
               on_off(true),
#else
               on_off(false),
#endif
#ifdef ARDCELL_WITH_SYSTEMD
               on_off(true),
#else
               on_off(false),
#endif
               on_off(charts_available()),
#ifdef ARDCELL_WITH_MPI
               on_off(true));
#else
               on_off(false));
#endif
#ifdef ARDCELL_WITH_SDL2
  // The live HUD's font (fonts-dejavu-core): a kiosk without it shows no HUD text.
  const std::string font(hud_font_path());
  std::fprintf(o, "hud font: %s\n",
               font.empty()                    ? "none (install fonts-dejavu-core)"
               : std::filesystem::exists(font) ? font.c_str()
                                               : (font + " (missing)").c_str());
#endif
  std::fprintf(o, "cpu: %s\n", cpu_model().c_str());
  std::fprintf(o, "cpu features: %s\n", cpu_features().c_str());
  std::fprintf(o, "compiled for: %s\n", compiled_for().c_str());
  cpu_set_t set;
  CPU_ZERO(&set);
  const int usable = ::sched_getaffinity(0, sizeof set, &set) == 0 ? CPU_COUNT(&set) : 0;
  std::fprintf(o, "cores: %ld online, %d usable by this process\n", ::sysconf(_SC_NPROCESSORS_ONLN),
               usable);
  std::string names;
  for (const std::string& n : preset_names()) names += (names.empty() ? "" : " ") + n;
  std::fprintf(o, "scenes: %s\n", names.c_str());
  return kExitOk;
}

}  // namespace

void add_info_command(CLI::App& app, CliContext& ctx) {
  CLI::App* info =
      app.add_subcommand("info", "Version, build options, CPU features and core count");
  info->callback([&ctx] { ctx.exit_code = do_info(ctx); });
}

}  // namespace ardcell
