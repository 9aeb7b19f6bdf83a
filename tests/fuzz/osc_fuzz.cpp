// libFuzzer target for the OSC handlers of `ardcell live --osc` (drivers/osc_liblo.h
// OscServer::dispatch: liblo's decoding, then the address and argument checks that turn a
// datagram into a LiveCommand or a stroke sample): any datagram is handled or rejected, never
// more than one command and its activity note, never a crash; the queues are drained after each
// input as the live loop does. Presets resolve in a temporary preset folder with one file (and a
// symlink out of it, which must stay refused). Seeds: tests/fuzz/corpus/osc_fuzz/ (one message
// of each address, valid and not).
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include "drivers/osc_liblo.h"

namespace {

struct Fixture {
  ardcell::CommandQueue commands;
  ardcell::StrokeRing strokes{4096};
  ardcell::RemoteLog log{nullptr};  // counted, not printed: the fuzzer's output stays readable
  std::unique_ptr<ardcell::OscServer> server;
  std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("ardcell_osc_fuzz_" + std::to_string(::getpid()));
  Fixture() {
    namespace fs = std::filesystem;
    fs::create_directories(dir);
    std::ofstream(dir / "mine.toml") << "name = \"mine\"\n[grid]\nsize = [16, 16]\n";
    std::error_code ec;
    fs::create_symlink("/etc/hostname", dir / "out.toml", ec);
    ardcell::Status error = ardcell::Status::ok();
    server =
        ardcell::OscServer::start(0, "127.0.0.1", commands, strokes, log, error, {dir.string()});
    if (!server) std::abort();
  }
  ~Fixture() {
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace ardcell;
  static Fixture f;
  const int64_t rejected = f.server->rejected();
  const bool ok = f.server->dispatch(data, size);
  // Handled, or rejected (counted once, with its logged line).
  if (f.server->rejected() != rejected + (ok ? 0 : 1)) std::abort();
  int popped = 0;
  LiveCommand c;
  while (f.commands.pop(c)) {
    ++popped;
    if (c.kind == LiveCommandKind::kSelectPreset) {
      // Only the folder's own file, or a built-in name: never the symlink's target.
      const std::string text(c.text.data());
      if (text.find("hostname") != std::string::npos || text.find("out.toml") != std::string::npos)
        std::abort();
    }
  }
  if (popped > 2) std::abort();
  StrokeSample s;
  while (f.strokes.pop(s)) {
  }
  return 0;
}
