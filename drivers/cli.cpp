#include "drivers/cli.h"

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <exception>

namespace ardcell {

// The subcommands, in --help order. Each X(name) is a function
// `void add_<name>_command(CLI::App&, CliContext&)` defined in that area's drivers/*.cpp;
// adding a subcommand is one line here.
#define ARDCELL_SUBCOMMANDS(X) \
  X(run)                       \
  X(info)                      \
  X(bench)                     \
  X(devices)                   \
  X(tablet)                    \
  X(live)                      \
  X(propagator)                \
  X(texture)                   \
  X(surface)

#define ARDCELL_DECLARE_COMMAND(name) void add_##name##_command(CLI::App&, CliContext&);
ARDCELL_SUBCOMMANDS(ARDCELL_DECLARE_COMMAND)
#undef ARDCELL_DECLARE_COMMAND

namespace {

#define ARDCELL_LIST_COMMAND(name) &add_##name##_command,
constexpr CommandInstaller kCommands[] = {ARDCELL_SUBCOMMANDS(ARDCELL_LIST_COMMAND)};
#undef ARDCELL_LIST_COMMAND

std::string one_line(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

// The deepest subcommand the user named, e.g. "run" ("" for the top level).
std::string chosen_command(const CLI::App& app) {
  std::string name;
  const CLI::App* cur = &app;
  while (true) {
    const auto subs = cur->get_subcommands();
    if (subs.empty()) break;
    cur = subs.front();
    name += (name.empty() ? "" : " ") + cur->get_name();
  }
  return name;
}

constexpr int kStopSignals[] = {SIGINT, SIGTERM, SIGHUP};
std::atomic<bool> g_stop_requested{false};
std::atomic<int> g_stop_signal{0};

extern "C" void on_stop_signal(int sig) {
  int none = 0;
  g_stop_signal.compare_exchange_strong(none, sig);
  g_stop_requested.store(true);
}

}  // namespace

StopSignals::StopSignals() {
  g_stop_requested.store(false);
  g_stop_signal.store(0);
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART;
  for (int i = 0; i < 3; ++i) ::sigaction(kStopSignals[i], &sa, &previous_[i]);
}

StopSignals::~StopSignals() {
  // Once a signal asked the command to stop, it is on its way out with 128 + that signal: a
  // later one (a second Ctrl-C, systemd repeating SIGTERM) must not kill it between here and
  // the exit, so the handlers stay.
  if (g_stop_signal.load() != 0) return;
  for (int i = 0; i < 3; ++i) ::sigaction(kStopSignals[i], &previous_[i], nullptr);
}

const std::atomic<bool>& StopSignals::requested() { return g_stop_requested; }
int StopSignals::signal() { return g_stop_signal.load(); }
int StopSignals::exit_code(int otherwise) {
  const int sig = g_stop_signal.load();
  return sig ? 128 + sig : otherwise;
}

CLI::Validator finite_range(double lo, double hi) {
  const std::string range =
      "a finite number in [" + CLI::detail::to_string(lo) + ", " + CLI::detail::to_string(hi) + "]";
  return CLI::Validator(
      [lo, hi, range](std::string& text) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v) || v < lo ||
            v > hi)
          return "expected " + range + ", got '" + text + "'";
        return "";
      },
      "FINITE in [" + CLI::detail::to_string(lo) + ", " + CLI::detail::to_string(hi) + "]");
}

int cli_usage_error(CliContext& ctx, const std::string& command, const std::string& message) {
  // One line per problem: a message listing several (a preset's) has one per line.
  size_t begin = 0;
  bool printed = false;
  while (begin <= message.size()) {
    size_t end = message.find('\n', begin);
    if (end == std::string::npos) end = message.size();
    const std::string line = one_line(message.substr(begin, end - begin));
    if (!line.empty() || (!printed && end == message.size())) {
      std::fprintf(ctx.err, "ardcell%s%s: %s\n", command.empty() ? "" : " ", command.c_str(),
                   line.c_str());
      printed = true;
    }
    begin = end + 1;
  }
  std::fflush(ctx.err);
  return kExitUsage;
}

int run_cli(int argc, char** argv) {
  CliContext ctx;
  CLI::App app{"ardcell: real-time advection-reaction-diffusion (stable fluids + Kim & Lin RD)",
               "ardcell"};
  app.set_version_flag("--version", std::string("ardcell ") + ARDCELL_VERSION);
  app.require_subcommand(0, 1);
  app.footer("Run `ardcell <command> --help` for the options of each command.");
  for (CommandInstaller install : kCommands) install(app, ctx);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    const std::string command = chosen_command(app);
    return cli_usage_error(ctx, command,
                           std::string(e.what()) + " (see ardcell" +
                               (command.empty() ? "" : " " + command) + " --help)");
  } catch (const std::exception& e) {
    std::fprintf(ctx.err, "ardcell: %s\n", one_line(e.what()).c_str());
    return kExitFailure;
  }
  if (app.get_subcommands().empty()) {
    std::fputs(app.help().c_str(), ctx.out);
    return kExitOk;
  }
  return ctx.exit_code;
}

}  // namespace ardcell
