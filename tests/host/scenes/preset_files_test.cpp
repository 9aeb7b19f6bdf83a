// presets/*.toml are the built-in scenes written as TOML (task: every scene is a TOML file).
// This test keeps them in step with the registry:
//   ARDCELL_REGENERATE_PRESETS=1 build/<dir>/preset_files_test   rewrites them (temp + rename)
// and without the variable it fails, naming the file and the first differing key, when a file
// no longer equals preset_to_toml(built-in scene).
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "host/scenes/preset.h"
#include "host/scenes/scene_registry.h"

namespace ardcell {
namespace {

namespace fs = std::filesystem;

const fs::path kPresetDir = ARDCELL_SOURCE_DIR "/presets";

std::string generated_text(const SceneConfig& scene) {
  return "# Generated from the built-in scene '" + scene.name +
         "' (host/scenes/scene_registry.h); regenerate with\n"
         "#   ARDCELL_REGENERATE_PRESETS=1 build/<dir>/preset_files_test\n" +
         preset_to_toml(preset_from_scene(scene));
}

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

bool regenerate() {
  const char* v = std::getenv("ARDCELL_REGENERATE_PRESETS");
  return v && std::string(v) == "1";
}

void write_atomically(const fs::path& path, const std::string& text) {
  const fs::path tmp = path.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    ASSERT_TRUE(out) << tmp;
    out << text;
    out.close();
    ASSERT_TRUE(out) << tmp;
  }
  fs::rename(tmp, path);
}

TEST(PresetFiles, EveryBuiltinSceneHasItsGeneratedFile) {
  for (const SceneEntry& e : builtin_scenes().entries()) {
    const SceneConfig scene = e.make();
    const fs::path path = kPresetDir / (e.name + ".toml");
    const std::string expected = generated_text(scene);
    if (regenerate()) {
      if (!fs::exists(path) || read_text(path) != expected) write_atomically(path, expected);
      continue;
    }
    ASSERT_TRUE(fs::exists(path)) << path << " is missing; run ARDCELL_REGENERATE_PRESETS=1 "
                                  << "preset_files_test";
    const std::string text = read_text(path);
    Preset file;
    const Status s = parse_preset(text, path.string(), file);
    ASSERT_TRUE(s.is_ok()) << s.message();
    EXPECT_EQ(preset_difference(file, preset_from_scene(scene)), "") << path;
    EXPECT_EQ(text, expected) << path << " differs from the built-in scene; regenerate it";
  }
}

TEST(PresetFiles, NamesFindTheEmbeddedFileWithTheBuiltinsValues) {
  for (const SceneEntry& e : builtin_scenes().entries()) {
    Preset p;
    const Status s = load_preset(e.name, p);
    ASSERT_TRUE(s.is_ok()) << s.message();
    EXPECT_EQ(p.source, "embedded:" + e.name) << "rebuild after adding presets/" << e.name;
    EXPECT_EQ(preset_difference(p, preset_from_scene(e.make())), "") << e.name;
    // A path loads the same preset.
    Preset by_path;
    ASSERT_TRUE(load_preset((kPresetDir / (e.name + ".toml")).string(), by_path).is_ok());
    EXPECT_EQ(preset_difference(p, by_path), "") << e.name;
  }
}

// docs/presets.md's key reference: one row per key of the table in host/scenes/preset.cpp.
std::string key_reference() {
  std::string out = "| key | type and range | live | meaning |\n|---|---|---|---|\n";
  for (const ParamSpec& spec : preset_params()) {
    std::string expectation = param_expectation(spec);
    std::string escaped;
    for (char c : expectation) escaped += c == '|' ? std::string("\\|") : std::string(1, c);
    std::string help;
    for (char c : spec.help) help += c == '|' ? std::string("\\|") : std::string(1, c);
    const char* live = spec.kind == ParamKind::kString ? "-" : spec.structural ? "rebuild" : "live";
    out += "| `" + std::string(spec.key) + "` | " + escaped + " | " + live + " | " + help + " |\n";
  }
  return out;
}

TEST(PresetFiles, DocsKeyReferenceListsEveryKey) {
  const fs::path readme = ARDCELL_SOURCE_DIR "/docs/presets.md";
  const std::string text = read_text(readme);
  const std::string begin = "<!-- preset keys begin -->\n", end = "<!-- preset keys end -->";
  const size_t b = text.find(begin), e = text.find(end);
  ASSERT_NE(b, std::string::npos) << "docs/presets.md lost its preset key markers";
  ASSERT_NE(e, std::string::npos);
  ASSERT_LT(b, e);
  const std::string current = text.substr(b + begin.size(), e - b - begin.size());
  const std::string expected = key_reference();
  if (regenerate()) {
    if (current != expected)
      write_atomically(readme, text.substr(0, b + begin.size()) + expected + text.substr(e));
    return;
  }
  EXPECT_EQ(current, expected) << "docs/presets.md key reference is stale; regenerate it";
}

}  // namespace
}  // namespace ardcell
