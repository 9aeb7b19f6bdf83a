// libFuzzer target for a saved state's meta.json (host/io/state_io.h read_state_meta, then
// apply_preset_parameters as --load-state does): the input is written as meta.json of a
// temporary folder; it is either read, with a size in range, a scene name and parameters that
// set a preset or give a message naming meta.json, or refused with a message naming meta.json.
// Seeds: tests/fuzz/corpus/state_meta_fuzz/ (meta.json files --save-state writes, and broken
// ones).
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "host/io/npy.h"
#include "host/io/state_io.h"
#include "host/scenes/preset.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace ardcell;
  namespace fs = std::filesystem;
  // A folder of its own, removed at exit.
  static const struct Folder {
    fs::path path =
        fs::temp_directory_path() / ("ardcell_state_meta_fuzz_" + std::to_string(::getpid()));
    Folder() {
      if (!fs::create_directories(path) && !fs::is_directory(path)) std::abort();
    }
    ~Folder() {
      std::error_code ec;
      fs::remove_all(path, ec);
    }
  } folder;
  const fs::path& dir = folder.path;
  {
    std::ofstream out(dir / "meta.json", std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  }
  SavedStateMeta meta;
  const Status s = read_state_meta(dir, meta);
  const std::string what = (dir / "meta.json").string();
  if (!s.is_ok()) {
    if (s.message().find("meta.json") == std::string::npos) std::abort();
    return 0;
  }
  if (meta.scene.empty() || meta.size.x < 1 || meta.size.y < 1 || meta.size.x > kNpyMaxSide ||
      meta.size.y > kNpyMaxSide)
    std::abort();
  Preset preset;
  const Status p = apply_preset_parameters(meta.parameters, what, preset);
  if (!p.is_ok() && p.message().find("meta.json") == std::string::npos) std::abort();
  return 0;
}
