#pragma once
// The `ardcell` command line (CLI11): one subcommand per area, each with its own --help.
//
// Adding a subcommand: define `void add_<name>_command(CLI::App& app, CliContext& ctx)` in your
// own drivers/*.cpp (it calls app.add_subcommand(...) and sets a callback that stores its exit
// code in ctx.exit_code), then add the one line `X(<name>)` to ARDCELL_SUBCOMMANDS in
// drivers/cli.cpp. Report bad input with cli_usage_error (one line, exit code 2).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <string>

namespace ardcell {

inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;  // a run that started failed (disk full, ffmpeg died)
inline constexpr int kExitUsage = 2;    // bad input: flags, scenes, sizes, folders, states

// What the subcommands of one invocation share.
struct CliContext {
  int exit_code = kExitOk;  // returned by main(); set by the subcommand that ran
  std::FILE* out = stdout;
  std::FILE* err = stderr;
};

using CommandInstaller = void (*)(CLI::App& app, CliContext& ctx);

// Prints "ardcell <command>: <message>" as one line on ctx.err (newlines in message become
// spaces) and returns kExitUsage, so a callback can write `ctx.exit_code = cli_usage_error(...)`.
int cli_usage_error(CliContext& ctx, const std::string& command, const std::string& message);

// The subcommands defined here.
void add_run_command(CLI::App& app, CliContext& ctx);
void add_info_command(CLI::App& app, CliContext& ctx);

// The whole program: parses argv, runs the chosen subcommand, returns the exit code.
int run_cli(int argc, char** argv);

}  // namespace ardcell
