// Saved states: bit-exact round trip of every field and of time/step, meta.json contents, the
// preset parameters, replacement of a previous state without a half-written moment, and one
// clear error (state untouched) for each kind of damage.
#include "host/io/state_io.h"

#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>

#include "host/io/npy.h"

namespace ardcell {
namespace {

namespace fs = std::filesystem;

SimState make_state(Int2 size, float seed) {
  SimState s;
  s.size = size;
  s.h = 1.0 / size.x;
  s.dt = 0.0123456789;
  s.time = 1.2345678901234567;
  s.rd_time = 24.691357802469134;
  s.step = 100;
  s.u = FieldF(size, 1);
  s.v = FieldF(size, 1);
  s.p = FieldF(size, 1);
  s.dye = FieldF(size, 1);
  int k = 0;
  s.for_each_field([&](std::string_view, FieldF& f) {
    ++k;
    for (int y = 0; y < size.y; ++y)
      for (int x = 0; x < size.x; ++x)
        f(x, y) = seed * float(k) + std::sin(0.3f * float(x * k) + 0.7f * float(y)) / 3.0f;
  });
  return s;
}

SceneConfig make_scene() {
  SceneConfig c;
  c.name = "cavity";
  c.description = "test";
  c.size = {9, 6};
  c.fluid.viscosity = 0.0025;
  c.output.show = "vorticity";
  return c;
}

bool same_fields(const SimState& a, const SimState& b) {
  bool same = true;
  a.for_each_field([&](std::string_view name, const FieldF& fa) {
    const FieldF* fb = nullptr;
    b.for_each_field([&](std::string_view n, const FieldF& f) {
      if (n == name) fb = &f;
    });
    if (!fb) {
      same = false;
      return;
    }
    for (int y = 0; y < a.size.y; ++y)
      if (std::memcmp(fa.row(y), fb->row(y), sizeof(float) * std::size_t(a.size.x)) != 0)
        same = false;
  });
  return same;
}

class StateIoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() /
            ("ardcell_state_test_" + std::to_string(::getpid()) + "_" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root_);
    fs::create_directories(root_);
    dir_ = root_ / "state";
  }
  void TearDown() override { fs::remove_all(root_); }
  std::vector<std::string> entries(const fs::path& d) const {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(d)) out.push_back(e.path().filename().string());
    std::sort(out.begin(), out.end());
    return out;
  }
  // Saves, then loads into a fresh state of the same shape; returns the load status.
  Status load_into(SimState& target) {
    SavedStateMeta meta;
    if (Status s = read_state_meta(dir_, meta); !s) return s;
    return load_state_fields(dir_, meta, target);
  }
  fs::path root_, dir_;
};

TEST_F(StateIoTest, RoundTripIsBitExactAndMetaDescribesTheState) {
  const SimState s = make_state({9, 6}, 0.5f);
  ASSERT_TRUE(save_state(dir_, s, make_scene()));
  EXPECT_EQ(entries(root_), std::vector<std::string>{"state"});  // no temporary left
  EXPECT_EQ(entries(dir_),
            (std::vector<std::string>{"dye.npy", "meta.json", "p.npy", "u.npy", "v.npy"}));
  SavedStateMeta meta;
  Status st = read_state_meta(dir_, meta);
  ASSERT_TRUE(st) << st.message();
  EXPECT_EQ(meta.scene, "cavity");
  EXPECT_EQ(meta.size, (Int2{9, 6}));
  EXPECT_EQ(meta.h, s.h);
  EXPECT_EQ(meta.dt, s.dt);
  EXPECT_EQ(meta.time, s.time);  // doubles survive JSON exactly
  EXPECT_EQ(meta.rd_time, s.rd_time);
  EXPECT_EQ(meta.step, 100);
  EXPECT_EQ(meta.fields, (std::vector<std::string>{"u", "v", "p", "dye"}));
  EXPECT_EQ(meta.parameters.at("fluid.viscosity").get<double>(), 0.0025);
  EXPECT_EQ(meta.parameters.at("output.show").get<std::string>(), "vorticity");
  EXPECT_EQ(meta.parameters.at("grid.size"), nlohmann::json({9, 6}));

  SimState t = make_state({9, 6}, -7.0f);
  t.time = 0;
  t.rd_time = 0;
  t.step = 0;
  ASSERT_TRUE(load_state_fields(dir_, meta, t));
  EXPECT_TRUE(same_fields(s, t));
  EXPECT_EQ(t.time, s.time);
  EXPECT_EQ(t.rd_time, s.rd_time);
  EXPECT_EQ(t.step, s.step);

  // The arrays are (ny, nx) with row y = grid row y.
  NpyArray u;
  ASSERT_TRUE(read_npy(dir_ / "u.npy", u));
  EXPECT_EQ(u.ny, 6);
  EXPECT_EQ(u.nx, 9);
  EXPECT_EQ(u.at(8, 5), s.u(8, 5));
}

// A state saved before the RD's own time was recorded has no "rd_time": it is taken as "time".
TEST_F(StateIoTest, AStateWithoutRdTimeTakesTheSceneTime) {
  const SimState s = make_state({9, 6}, 0.5f);
  ASSERT_TRUE(save_state(dir_, s, make_scene()));
  nlohmann::json j = nlohmann::json::parse(std::ifstream(dir_ / "meta.json"));
  ASSERT_EQ(j.at("rd_time").get<double>(), s.rd_time);
  j.erase("rd_time");
  std::ofstream(dir_ / "meta.json") << j.dump();
  SavedStateMeta meta;
  ASSERT_TRUE(read_state_meta(dir_, meta));
  EXPECT_EQ(meta.rd_time, s.time);
}

TEST_F(StateIoTest, PresetParametersRoundTrip) {
  Preset a = preset_from_scene(make_scene());
  a.scene.dt = 0.037;
  a.scene.fluid.lid_speed = -2.5;
  a.scene.rd.enabled = true;
  a.scene.output.colormap = "magma";
  const nlohmann::json j = preset_parameters_to_json(a);
  Preset b = preset_from_scene(SceneConfig{});
  ASSERT_TRUE(apply_preset_parameters(j, "meta.json", b));
  EXPECT_EQ(preset_difference(a, b), "");
  b.scene.fluid.lid_speed = 1.0;
  EXPECT_NE(preset_difference(a, b), "");  // the comparison can fail

  Status s = apply_preset_parameters({{"fluid.viscosity", "thick"}}, "m.json", b);
  ASSERT_FALSE(s);
  EXPECT_NE(s.message().find("m.json: parameter 'fluid.viscosity'"), std::string::npos);
  s = apply_preset_parameters({{"fluid.nonsense", 1}}, "m.json", b);
  ASSERT_FALSE(s);
  EXPECT_NE(s.message().find("unknown parameter 'fluid.nonsense'"), std::string::npos);
  s = apply_preset_parameters({{"output.show", "temperature"}}, "m.json", b);
  ASSERT_FALSE(s);
}

TEST_F(StateIoTest, AStateOfACustomPresetResumesFromItsParametersAndSaysSo) {
  // A built-in scene: its own preset with the saved parameters over it, and no notice.
  ASSERT_TRUE(save_state(dir_, make_state({9, 6}, 1.0f), make_scene()));
  SavedStateMeta meta;
  ASSERT_TRUE(read_state_meta(dir_, meta));
  Preset p;
  std::string notice = "stale";
  Status s = saved_state_preset(dir_, meta, p, notice);
  ASSERT_TRUE(s) << s.message();
  EXPECT_EQ(notice, "");
  EXPECT_EQ(p.scene.name, "cavity");
  EXPECT_EQ(p.scene.size, (Int2{9, 6}));
  EXPECT_EQ(p.scene.fluid.viscosity, 0.0025);

  // A custom preset's scene (no such built-in): every saved key makes it, with one line.
  SceneConfig custom = make_scene();
  custom.name = "my-ink";
  custom.fluid.lid_speed = -1.5;
  ASSERT_TRUE(save_state(dir_, make_state({9, 6}, 1.0f), custom));
  ASSERT_TRUE(read_state_meta(dir_, meta));
  s = saved_state_preset(dir_, meta, p, notice);
  ASSERT_TRUE(s) << s.message();
  EXPECT_EQ(notice, "state " + dir_.string() +
                        " was saved from scene 'my-ink', which is not built in: resuming from "
                        "the parameters saved with it");
  EXPECT_EQ(p.scene.name, "my-ink");
  EXPECT_EQ(p.scene.fluid.lid_speed, -1.5);
  EXPECT_EQ(p.scene.fluid.viscosity, 0.0025);
  EXPECT_EQ(preset_difference(preset_from_scene(custom), p), "");

  // Neither built in nor complete: refused in one line, naming a missing key.
  meta.parameters.erase("fluid.viscosity");
  const Preset before = p;
  s = saved_state_preset(dir_, meta, p, notice);
  ASSERT_FALSE(s);
  EXPECT_EQ(notice, "");
  EXPECT_EQ(s.message().find('\n'), std::string::npos) << s.message();
  EXPECT_NE(s.message().find("scene 'my-ink' is not built in and \"parameters\" lacks "
                             "fluid.viscosity (expected a built-in scene, or every preset key"),
            std::string::npos)
      << s.message();
  EXPECT_EQ(preset_difference(before, p), "");  // untouched
  meta.parameters = nlohmann::json::object();
  s = saved_state_preset(dir_, meta, p, notice);
  ASSERT_FALSE(s);
  EXPECT_NE(s.message().find("more keys"), std::string::npos) << s.message();

  // The scene is a name, never a file to read; a strange one is shown escaped on one line.
  meta.scene = "/etc/passwd\n\x1b[2J";
  s = saved_state_preset(dir_, meta, p, notice);
  ASSERT_FALSE(s);
  EXPECT_NE(s.message().find("scene '/etc/passwd\\x0a\\x1b[2J' is not built in"), std::string::npos)
      << s.message();
}

TEST_F(StateIoTest, SavingAgainReplacesThePreviousStateCompletely) {
  ASSERT_TRUE(save_state(dir_, make_state({9, 6}, 1.0f), make_scene()));
  SimState second = make_state({9, 6}, 2.0f);
  second.A = FieldF({9, 6}, 1);
  second.A.fill(0.25f);
  second.step = 7;
  ASSERT_TRUE(save_state(dir_, second, make_scene()));
  EXPECT_EQ(entries(root_), std::vector<std::string>{"state"});
  SimState t = make_state({9, 6}, 0.0f);
  t.A = FieldF({9, 6}, 1);
  ASSERT_TRUE(load_into(t));
  EXPECT_TRUE(same_fields(second, t));
  EXPECT_EQ(t.step, 7);
}

TEST_F(StateIoTest, AnEmptyFolderIsUsedButAnUnrelatedOneIsNeverOverwritten) {
  fs::create_directories(dir_);
  ASSERT_TRUE(save_state(dir_, make_state({9, 6}, 1.0f), make_scene()));
  const fs::path other = root_ / "photos";
  fs::create_directories(other);
  std::ofstream(other / "holiday.jpg") << "jpeg";
  Status s = save_state(other, make_state({9, 6}, 1.0f), make_scene());
  ASSERT_FALSE(s);
  EXPECT_NE(s.message().find("is not an ardcell saved state"), std::string::npos) << s.message();
  EXPECT_EQ(entries(other), std::vector<std::string>{"holiday.jpg"});
  EXPECT_EQ(entries(root_), (std::vector<std::string>{"photos", "state"}));
}

TEST_F(StateIoTest, UnwritablePlaceFailsAndLeavesNothing) {
  std::ofstream(root_ / "file") << "x";
  Status s = save_state(root_ / "file" / "state", make_state({9, 6}, 1.0f), make_scene());
  ASSERT_FALSE(s);
  EXPECT_NE(s.message().find("file"), std::string::npos);
  EXPECT_EQ(entries(root_), std::vector<std::string>{"file"});
}

TEST_F(StateIoTest, EveryKindOfDamageGivesOneLineAndLeavesTheStateUntouched) {
  const SimState original = make_state({9, 6}, 1.0f);
  struct Damage {
    const char* name;
    std::function<void(const fs::path&)> apply;
    const char* expect;
  };
  auto rewrite_meta = [](const fs::path& d, auto edit) {
    nlohmann::json j = nlohmann::json::parse(std::ifstream(d / "meta.json"));
    edit(j);
    std::ofstream(d / "meta.json") << j.dump();
  };
  const Damage damages[] = {
      {"no folder", [](const fs::path& d) { fs::remove_all(d); }, "saved state not found"},
      {"no meta", [](const fs::path& d) { fs::remove(d / "meta.json"); }, "meta.json: not found"},
      {"bad json", [](const fs::path& d) { std::ofstream(d / "meta.json") << "{\"format\": "; },
       "not valid JSON"},
      {"other json",
       [&](const fs::path& d) { rewrite_meta(d, [](auto& j) { j["format"] = "x"; }); },
       "not an ardcell saved state"},
      // found by state_meta_fuzz: a "format" of another type threw out of the reader
      {"format array",
       [&](const fs::path& d) { rewrite_meta(d, [](auto& j) {
                                  j["format"] = {7540840, 2};
                                }); },
       "not an ardcell saved state"},
      {"version", [&](const fs::path& d) { rewrite_meta(d, [](auto& j) { j["version"] = 99; }); },
       "unsupported version"},
      {"size text", [&](const fs::path& d) { rewrite_meta(d, [](auto& j) { j["size"] = "big"; }); },
       "\"size\""},
      {"size other",
       [&](const fs::path& d) { rewrite_meta(d, [](auto& j) {
                                  j["size"] = {8, 6};
                                }); },
       "does not match the scene's 9x6"},
      {"negative dt", [&](const fs::path& d) { rewrite_meta(d, [](auto& j) { j["dt"] = -1; }); },
       "\"dt\""},
      {"rd_time text",
       [&](const fs::path& d) { rewrite_meta(d, [](auto& j) { j["rd_time"] = "late"; }); },
       "\"rd_time\""},
      {"no u listed",
       [&](const fs::path& d) {
         rewrite_meta(d, [](auto& j) { j["fields"] = {"v", "p", "dye"}; });
       },
       "lists no u field"},
      {"extra A",
       [&](const fs::path& d) {
         rewrite_meta(d, [](auto& j) { j["fields"] = {"u", "v", "p", "dye", "A"}; });
       },
       "has no A field"},
      {"unknown field",
       [&](const fs::path& d) {
         rewrite_meta(d, [](auto& j) { j["fields"] = {"u", "v", "p", "dye", "T"}; });
       },
       "\"fields\""},
      {"missing npy", [](const fs::path& d) { fs::remove(d / "p.npy"); }, "p.npy: not found"},
      {"truncated npy", [](const fs::path& d) { fs::resize_file(d / "v.npy", 100); }, "v.npy"},
      {"garbage npy", [](const fs::path& d) { std::ofstream(d / "dye.npy") << "hello"; },
       "dye.npy: not a NumPy"},
      {"wrong shape",
       [](const fs::path& d) {
         FieldF f({6, 9}, 0);
         ASSERT_TRUE(write_npy(d / "u.npy", f.view(f.interior())));
       },
       "u.npy: shape (9, 6)"},
      {"nan",
       [](const fs::path& d) {
         FieldF f({9, 6}, 0);
         f(4, 3) = std::numeric_limits<float>::quiet_NaN();
         ASSERT_TRUE(write_npy(d / "u.npy", f.view(f.interior())));
       },
       "(x=4, y=3) is not finite"},
  };
  for (const Damage& d : damages) {
    fs::remove_all(dir_);
    ASSERT_TRUE(save_state(dir_, original, make_scene()));
    d.apply(dir_);
    SimState t = make_state({9, 6}, 5.0f);
    const SimState before = t;
    Status s = load_into(t);
    ASSERT_FALSE(s) << d.name;
    EXPECT_NE(s.message().find(d.expect), std::string::npos) << d.name << ": " << s.message();
    EXPECT_EQ(s.message().find('\n'), std::string::npos) << s.message();
    EXPECT_TRUE(same_fields(before, t)) << d.name;
    EXPECT_EQ(t.step, before.step) << d.name;
  }
}

}  // namespace
}  // namespace ardcell
