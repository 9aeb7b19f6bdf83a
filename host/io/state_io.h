#pragma once
// Saved states (`ardcell run --save-state DIR`, `--load-state DIR`): a folder that holds every
// allocated float field of a SimState as float32 .npy (u.npy, v.npy, p.npy, dye.npy, A.npy,
// B.npy, theta0.npy; interior cells only, shape (ny, nx), row y = grid row y) and meta.json:
//
//   { "format": "ardcell-state", "version": 1, "ardcell_version": "0.1.0",
//     "scene": "cavity", "size": [nx, ny], "h": ..., "dt": ..., "time": ..., "step": ...,
//     "rd_time": ... (the RD's own time, rd.dt x rd.steps_per_frame per frame; absent in
//     states saved before it was recorded: taken as "time"),
//     "fields": ["u", "v", "p", "dye"],
//     "parameters": { "grid.size": [nx, ny], "fluid.viscosity": 0.01, ... } }
//
// "parameters" holds every preset key (host/scenes/preset.h) of the scene, so that loading rebuilds
// the same scene. The folder is written under a temporary name and renamed into place: a
// reader sees the previous state or the new one, never a mixture or a half-written file.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "host/config/scene_config.h"
#include "host/config/sim_state.h"
#include "host/config/status.h"
#include "host/scenes/preset.h"

namespace ardcell {

inline constexpr int kStateFormatVersion = 1;

struct SavedStateMeta {
  std::string scene;  // the scene or preset name it was made from
  Int2 size;
  double h = 0, dt = 0, time = 0, rd_time = 0;
  int64_t step = 0;
  std::vector<std::string> fields;  // the .npy files present, by field name
  nlohmann::json parameters;        // preset key -> value
};

// Every preset parameter of `preset` as a JSON object keyed by the dotted key.
nlohmann::json preset_parameters_to_json(const Preset& preset);
// Sets each key of `parameters` on `preset` (validated by the preset table). `what` names the
// source in messages ("state/meta.json").
Status apply_preset_parameters(const nlohmann::json& parameters, const std::string& what,
                               Preset& preset);

// Writes `state` (made by `scene`) to dir, replacing a previous saved state there. dir must
// be new, empty, or a saved state; its parent folders are created.
Status save_state(const std::filesystem::path& dir, const SimState& state,
                  const SceneConfig& scene);

// Checks before a run that save_state(dir, ...) can write there: dir new (its nearest existing
// ancestor writable), an empty folder or a previous saved state, in a writable folder.
Status check_state_destination(const std::filesystem::path& dir);

// Reads and validates dir/meta.json.
Status read_state_meta(const std::filesystem::path& dir, SavedStateMeta& meta);

// The preset a saved state resumes, its grid the saved size. A built-in scene (an embedded
// preset or a built-in scene, never a file: meta.json names a scene, not a path to read) gets
// the saved parameters over its own. A scene that is not built in (a custom preset's) resumes
// from the saved parameters alone, which must then name every preset key, and `notice` gets
// one line saying so; empty otherwise.
Status saved_state_preset(const std::filesystem::path& dir, const SavedStateMeta& meta,
                          Preset& preset, std::string& notice);

// Reads every field `state` has allocated from dir (sizes must match meta and the state; every
// value finite), then sets time and step from meta. On failure `state` is left unchanged.
Status load_state_fields(const std::filesystem::path& dir, const SavedStateMeta& meta,
                         SimState& state);

}  // namespace ardcell
