#pragma once
// The `ardcell` command line (CLI11): one subcommand per area, each with its own --help.
//
// Adding a subcommand: define `void add_<name>_command(CLI::App& app, CliContext& ctx)` in your
// own drivers/*.cpp (it calls app.add_subcommand(...) and sets a callback that stores its exit
// code in ctx.exit_code), then add the one line `X(<name>)` to ARDCELL_SUBCOMMANDS in
// drivers/cli.cpp. Report bad input with cli_usage_error (one line, exit code 2).
#include <time.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <string>

namespace ardcell {

inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;  // a run that started failed (disk full, ffmpeg died)
inline constexpr int kExitUsage = 2;    // bad input: flags, scenes, sizes, folders, states

// What the subcommands of one invocation share.
// CPU time this process has used (every thread, exec and dynamic loading included).
inline double process_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

struct CliContext {
  int exit_code = kExitOk;  // returned by main(); set by the subcommand that ran
  std::FILE* out = stdout;
  std::FILE* err = stderr;
  // When main() made it, and the CPU time the process had used by then (exec, the dynamic
  // loader, static initialisers: work the process does without waiting): `run --stats` reports
  // the start-up from them.
  std::chrono::steady_clock::time_point main_started = std::chrono::steady_clock::now();
  double cpu_before_main_s = process_cpu_seconds();
};

using CommandInstaller = void (*)(CLI::App& app, CliContext& ctx);

// Prints "ardcell <command>: <message>" on ctx.err, one line per line of `message` (a preset
// with several problems gives one line each, as parse_preset returns them; empty lines are
// dropped) and returns kExitUsage, so a callback can write `ctx.exit_code = cli_usage_error(...)`.
int cli_usage_error(CliContext& ctx, const std::string& command, const std::string& message);

// SIGINT, SIGTERM and SIGHUP end `run`, `live` and `tablet record` the way Esc does: while a
// StopSignals lives, the handler only records the signal and sets requested(), which the loop
// polls; the command then finishes its files (recording, saved state, frames) and returns
// exit_code(). Installed with sigaction, so a disposition inherited as ignored (a script's `&`)
// is replaced too. Keep it alive until the files are finished and renamed: a second signal
// during finishing is recorded, never cuts the rename short. The destructor restores what was
// there before - unless a signal asked to stop: the command is exiting then, and a later signal
// must not kill it on the way out.
class StopSignals {
 public:
  StopSignals();
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;
  static const std::atomic<bool>& requested();
  static int signal();  // the first signal received, 0 for none
  // 128 + the signal when one ended the command (130 SIGINT, 143 SIGTERM), else `otherwise`.
  static int exit_code(int otherwise);

 private:
  struct sigaction previous_[3];
};

// A CLI11 check for a numeric flag that is no preset key (--fps, --attract): a finite number
// in [lo, hi]; NaN and infinities are refused (CLI::Range lets NaN through).
CLI::Validator finite_range(double lo, double hi);

// The subcommands defined here.
void add_run_command(CLI::App& app, CliContext& ctx);
void add_info_command(CLI::App& app, CliContext& ctx);

// The whole program: parses argv, runs the chosen subcommand, returns the exit code.
int run_cli(int argc, char** argv);

}  // namespace ardcell
