#pragma once
// What a surface run is made of, for `ardcell surface` and `ardcell live PRESET --shape`: the
// control mesh (a built-in shape, a mesh Debian ships, or a user's OBJ/OFF file) and a flat
// preset's reaction-diffusion carried onto the surface (its model and parameters, rates, step and
// start), with rates in surface units so that the pattern's wavelength is set by `length`, the
// surface length one flat cell stands for.
#include <cstdint>
#include <optional>
#include <string>

#include "host/config/status.h"
#include "host/scenes/preset.h"
#include "host/surface/poly_mesh.h"
#include "host/surface/surface_fluid.h"
#include "host/surface/surface_gray_scott.h"

namespace ardcell {

// "" when N (cells a patch side) is a power of two in 2..1024, else the line naming it.
std::string patch_cells_problem(int n);

// "torus, cube-sphere, genus2, eight or elephant": the names surface_control_mesh takes.
const char* surface_shape_names();

// The control mesh: the file `mesh_path` (OBJ or OFF) when not empty, else the shape: torus (32
// patches), cube-sphere (24), genus2 (a double torus, 50) built here, or eight and elephant from
// Debian's libcgal-demo (extracted by CMake into ARDCELL_MESH_DIR; the environment variable of
// that name, when set, names another folder). `label` is what messages about the mesh start with
// ("FILE" or "--shape eight"; empty for the procedural shapes).
Status surface_control_mesh(const std::string& shape, const std::string& mesh_path, PolyMesh& mesh,
                            std::string& label);

// A flat scene's reaction-diffusion as a surface can take it: what `preset` sets, in the flat
// grid's units (cells).
struct PresetRd {
  ReactionParams reaction;
  // Rates in cells^2 per unit time: D times the isotropic conductivity over h^2, as the flat
  // scene diffuses (h its cell: rd.cell_size, or the domain's width over its cells).
  double diffusion_a = 0, diffusion_b = 0, dt = 1;
  SurfaceGrayScott::Start start;  // radius in cells
  Int2 grid{};                    // the flat scene's cells (its spots' density)
  int steps_per_frame = 1;
  std::string name;
};
// The first setting a surface cannot take, as one line (without the preset's name): no RD,
// another operator than the Laplacian, anisotropy, a reaction table or map, a start laid out on
// the flat grid.
Status preset_rd(const Preset& preset, PresetRd& out);
// The parts of `scene` a running surface takes live (rates, step, reaction, steps a frame, the
// start's values): into `out`, false (out untouched) when the reaction's parameters or the step
// are out of range. Allocates nothing.
bool update_preset_rd(const SceneConfig& scene, PresetRd& out);

// The preset's RD on a surface of `area` where a flat cell stands for `length`: rates scaled by
// length^2, the preset's step, Kim & Lin's implicit reaction; the start's spots at the same
// density per flat cell, their radius in surface units.
SurfaceRdParams surface_rd_params(const PresetRd& flat, double length);

// --fluid's value (`ardcell surface` and `ardcell live`): gravity or walk; else the line naming
// it.
Status parse_fluid_force(const std::string& value, FluidForce& out);
// Whether `preset` can run as a surface fluid (`ardcell live --fluid`): it must have a fluid
// (fluid.scene other than none); one line (without the preset's name) when it has none.
Status preset_fluid(const Preset& preset);
// What a surface fluid takes from a flat scene, live or at the start: fluid.viscosity and
// fluid.dye_diffusion as surface areas per unit time (the flat domain's unit length is the
// surface's), fluid.conserve_dye unless `conserve_dye` overrides it. Allocates nothing.
void apply_preset_fluid(const SceneConfig& scene, const std::optional<bool>& conserve_dye,
                        SurfaceFluidParams& params);
SurfaceGrayScott::Start surface_start(const PresetRd& flat, double length, double area);

}  // namespace ardcell
