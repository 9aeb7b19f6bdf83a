#include "host/surface/surface_scene.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "host/surface/procedural_mesh.h"
#include "kernels/reaction.h"

namespace ardcell {
namespace {

// Sculpture-like meshes Debian ships in libcgal-demo's /usr/share/doc/libcgal-dev/data.tar.gz.
// CMake extracts them at configure time into ARDCELL_MESH_DIR (no download).
struct PackagedShape {
  const char* name;
  const char* file;
};
constexpr PackagedShape kPackagedShapes[] = {{"eight", "eight.off"}, {"elephant", "elephant.off"}};

std::filesystem::path packaged_mesh_dir() {
  if (const char* dir = std::getenv("ARDCELL_MESH_DIR"); dir && *dir) return dir;
#ifdef ARDCELL_MESH_DIR
  return ARDCELL_MESH_DIR;
#else
  return {};
#endif
}

}  // namespace

std::string patch_cells_problem(int n) {
  if (n >= 2 && n <= 1024 && (n & (n - 1)) == 0) return "";
  return "--patch-cells " + std::to_string(n) + ": expected a power of two in 2..1024";
}

const char* surface_shape_names() { return "torus, cube-sphere, genus2, eight or elephant"; }

Status surface_control_mesh(const std::string& shape, const std::string& mesh_path, PolyMesh& mesh,
                            std::string& label) {
  if (!mesh_path.empty()) {
    label = mesh_path;
    return read_mesh(mesh_path, {}, mesh);
  }
  for (const PackagedShape& packaged : kPackagedShapes) {
    if (shape != packaged.name) continue;
    const std::filesystem::path path = packaged_mesh_dir() / packaged.file;
    std::error_code ec;
    if (!std::filesystem::exists(path, ec))
      return Status::error("--shape " + shape + ": " + path.string() +
                           " not found (install Debian's libcgal-demo and run cmake again, or "
                           "set ARDCELL_MESH_DIR to a folder holding " +
                           packaged.file + ")");
    label = "--shape " + shape;
    return read_mesh(path, {}, mesh);
  }
  label.clear();
  if (shape == "torus")
    mesh = torus_mesh(8, 4, 2.0, 0.8);
  else if (shape == "cube-sphere")
    mesh = cube_mesh(2);
  else if (shape == "genus2")
    mesh = genus2_mesh(1.0);
  else
    return Status::error("--shape '" + shape + "': expected " + surface_shape_names());
  return Status::ok();
}

Status preset_rd(const Preset& p, PresetRd& out) {
  const RdConfig& rd = p.scene.rd;
  if (!rd.enabled) return Status::error("rd.enabled is false (expected a scene with RD)");
  if (rd.diffusion_operator != RdOperator::kLaplacian)
    return Status::error(
        "rd.operator: a surface diffuses with its Laplace-Beltrami operator "
        "(expected laplacian)");
  if (rd.anisotropy.kind != AnisotropyKind::kIsotropic)
    return Status::error(
        "rd.anisotropy: the surface's diffusion is isotropic (expected "
        "isotropic)");
  if (rd.use_table || rd.map)
    return Status::error(
        "rd.table / rd.map: one reaction per cell, computed (expected "
        "neither)");
  if (rd.initial != RdInitialPattern::kUniform && rd.initial != RdInitialPattern::kRandomSpots)
    return Status::error(
        "rd.initial.pattern: squares, discs and stripes are laid out on a "
        "flat grid (expected uniform or random-spots)");
  if (!update_preset_rd(p.scene, out))
    return Status::error(
        "rd.reaction / rd.dt: out of range (expected the model's parameters and "
        "a positive step)");
  out.grid = p.scene.size;
  out.name = p.scene.name.empty() ? p.source : p.scene.name;
  return Status::ok();
}

bool update_preset_rd(const SceneConfig& scene, PresetRd& out) {
  const RdConfig& rd = scene.rd;
  const double dt = rd.dt > 0 ? rd.dt : scene.dt;
  if (reaction_params_problem(rd.reaction) || !(dt > 0) || !std::isfinite(dt)) return false;
  const double h = rd.cell_size > 0 ? rd.cell_size : scene.domain_width / scene.size.x;
  const double per_cell = rd.anisotropy.isotropic_value / (h * h);
  out.reaction = rd.reaction;
  out.diffusion_a = rd.diffusion_a * per_cell;
  out.diffusion_b = rd.diffusion_b * per_cell;
  out.dt = dt;
  out.steps_per_frame = rd.steps_per_frame;
  out.start.background_a = rd.background_a;
  out.start.background_b = rd.background_b;
  out.start.seed_a = rd.seed_a;
  out.start.seed_b = rd.seed_b;
  out.start.spots = rd.initial == RdInitialPattern::kRandomSpots ? rd.spots : 0;
  out.start.radius = rd.seed_radius;
  out.start.noise = rd.noise;
  out.start.seed = std::uint32_t(rd.seed);
  return true;
}

SurfaceRdParams surface_rd_params(const PresetRd& flat, double length) {
  SurfaceRdParams params;
  params.reaction = flat.reaction;
  params.diffusion_a = flat.diffusion_a * length * length;
  params.diffusion_b = flat.diffusion_b * length * length;
  params.dt = flat.dt;
  params.scheme = SurfaceReaction::kImplicit;
  return params;
}

Status parse_fluid_force(const std::string& value, FluidForce& out) {
  if (value == "gravity")
    out = FluidForce::kGravity;
  else if (value == "walk")
    out = FluidForce::kWalk;
  else
    return Status::error("--fluid '" + value + "': expected gravity or walk");
  return Status::ok();
}

Status preset_fluid(const Preset& p) {
  if (p.scene.fluid.kind == FluidSceneKind::kNone)
    return Status::error(
        "fluid.scene is none: --fluid runs a preset's fluid (expected a preset whose "
        "fluid.scene is cavity, obstacle, ink or table1)");
  return Status::ok();
}

void apply_preset_fluid(const SceneConfig& scene, const std::optional<bool>& conserve_dye,
                        SurfaceFluidParams& params) {
  params.viscosity = scene.fluid.viscosity;
  params.dye_diffusion = scene.fluid.dye_diffusion;
  params.conserve_dye = conserve_dye.value_or(scene.fluid.conserve_dye);
}

SurfaceGrayScott::Start surface_start(const PresetRd& flat, double length, double area) {
  SurfaceGrayScott::Start start = flat.start;
  const double flat_cells = double(flat.grid.x) * flat.grid.y;
  start.spots = int(std::lround(start.spots * (area / (length * length)) / flat_cells));
  start.radius *= length;
  return start;
}

}  // namespace ardcell
