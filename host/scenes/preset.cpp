#include "host/scenes/preset.h"

#include <toml++/toml.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <type_traits>

#include "host/io/user_file.h"
#include "host/paint/paint.h"
#include "host/render/colormap.h"
#include "host/scenes/scene_registry.h"

namespace ardcell {

namespace {

constexpr std::string_view kFluidScenes[] = {"none", "cavity", "obstacle", "ink", "table1"};
constexpr std::string_view kSolvers[] = {"jacobi", "rbgs", "iccg", "mg"};
constexpr std::string_view kShows[] = {"dye", "speed", "vorticity", "pressure", "A", "B"};
constexpr std::string_view kWalls[] = {"free-slip", "no-slip", "periodic"};
constexpr std::string_view kAdvection[] = {"semi-lagrangian", "maccormack"};
constexpr std::string_view kSides[] = {"left", "right", "bottom", "top"};
constexpr std::string_view kInflowProfiles[] = {"plug", "parabolic"};
constexpr std::string_view kObstacleBoundaries[] = {"staircase", "cut-cell"};
// In the order of the enums (kernels/reaction.h, anisotropy.h, stencil_operator.h, rd_config.h).
constexpr std::string_view kModels[] = {"gray-scott",      "turing",  "meinhardt",
                                        "fitzhugh-nagumo", "barkley", "barkley-turbulent"};
constexpr std::string_view kAnisotropies[] = {"isotropic", "witkin-kass", "lobes", "polar"};
constexpr std::string_view kBoundaries[] = {"periodic", "neumann", "dirichlet"};
constexpr std::string_view kSchemes[] = {"implicit", "explicit5",     "explicit9",
                                         "explicit", "semi-implicit", "crank-nicolson-am2",
                                         "sbdf2",    "etdrk4"};
constexpr std::string_view kOperators[] = {"laplacian", "generalized"};
constexpr std::string_view kSecondDerivatives[] = {"central", "savitzky-golay"};
constexpr std::string_view kTensorFields[] = {"uniform", "vortex", "radial"};
constexpr std::string_view kPatterns[] = {"uniform",      "centre-square", "seed-square",
                                          "random-spots", "stripe",        "centre-disc"};
constexpr std::string_view kColormaps[] = {"gray", "viridis", "magma", "rdbu"};
constexpr std::string_view kModes[] = {"deposit", "orient", "push", "obstacle", "erase"};

template <class T>
void assign_number(T& field, double v) {
  if constexpr (std::is_enum_v<T>)
    field = static_cast<T>(static_cast<int>(v));
  else if constexpr (std::is_same_v<T, bool>)
    field = v != 0.0;
  else
    field = static_cast<T>(v);
}
template <class T>
double read_number(const T& field) {
  if constexpr (std::is_enum_v<T>)
    return double(static_cast<int>(field));
  else
    return double(field);
}

// Index of `value` in a choice list stored as a string (colormap, show, mode).
double choice_index(std::span<const std::string_view> choices, const std::string& value) {
  for (size_t i = 0; i < choices.size(); ++i)
    if (choices[i] == value) return double(i);
  return -1;
}

#define ARD_ACCESS(expr)                                                                          \
  .get = [](const Preset& p) { return read_number(p.expr); },                                     \
  .set = [](Preset& p, double v) { assign_number(p.expr, v); }, .text = nullptr, .size = nullptr, \
  .floats = nullptr, .emitters = nullptr, .fill = 0,                                              \
  .single = std::is_same_v<std::remove_cvref_t<decltype(std::declval<Preset&>().expr)>, float>
#define ARD_NUMBER(key_, expr, lo, hi, structural_, help_)                        \
  ParamSpec {                                                                     \
    .key = key_, .kind = ParamKind::kNumber, .min = lo, .max = hi, .choices = {}, \
    .structural = structural_, .help = help_, ARD_ACCESS(expr)                    \
  }
#define ARD_INTEGER(key_, expr, lo, hi, structural_, help_)                        \
  ParamSpec {                                                                      \
    .key = key_, .kind = ParamKind::kInteger, .min = lo, .max = hi, .choices = {}, \
    .structural = structural_, .help = help_, ARD_ACCESS(expr)                     \
  }
#define ARD_BOOL(key_, expr, structural_, help_)                              \
  ParamSpec {                                                                 \
    .key = key_, .kind = ParamKind::kBool, .min = 0, .max = 1, .choices = {}, \
    .structural = structural_, .help = help_, ARD_ACCESS(expr)                \
  }
// A choice stored as an enum (its value is the index in `list`).
#define ARD_ENUM(key_, expr, list, structural_, help_)                                     \
  ParamSpec {                                                                              \
    .key = key_, .kind = ParamKind::kChoice, .min = 0, .max = double(std::size(list) - 1), \
    .choices = list, .structural = structural_, .help = help_, ARD_ACCESS(expr)            \
  }
// A choice stored as a string.
#define ARD_NAMED(key_, expr, list, structural_, help_)                                    \
  ParamSpec {                                                                              \
    .key = key_, .kind = ParamKind::kChoice, .min = 0, .max = double(std::size(list) - 1), \
    .choices = list, .structural = structural_, .help = help_,                             \
    .get = [](const Preset& p) { return choice_index(list, p.expr); },                     \
    .set =                                                                                 \
        [](Preset& p, double v) {                                                          \
          const auto i = size_t(v);                                                        \
          if (i < std::size(list)) p.expr.assign(list[i].data(), list[i].size());          \
        },                                                                                 \
    .text = [](Preset& p) -> std::string& { return p.expr; }                               \
  }
#define ARD_STRING(key_, expr, help_)                                           \
  ParamSpec {                                                                   \
    .key = key_, .kind = ParamKind::kString, .min = 0, .max = 0, .choices = {}, \
    .structural = false, .help = help_, .get = nullptr, .set = nullptr,         \
    .text = [](Preset& p) -> std::string& { return p.expr; }                    \
  }
#define ARD_SOLVER(prefix, member, structural_)                                             \
  ARD_ENUM(prefix ".kind", scene.fluid.member.kind, kSolvers, true,                         \
           "jacobi | rbgs (fixed sweeps) | iccg | mg (multigrid)"),                         \
      ARD_INTEGER(prefix ".iterations", scene.fluid.member.max_iterations, 1, 10000, false, \
                  "sweeps, CG iterations or V-cycles at full quality"),                     \
      ARD_NUMBER(prefix ".tolerance", scene.fluid.member.tolerance, 0, 1, false,            \
                 "relative residual to stop at; 0 runs every iteration")

#define ARD_RD_SOLVER(prefix, member)                                                    \
  ARD_ENUM(prefix ".kind", scene.rd.member.kind, kSolvers, true,                         \
           "jacobi | rbgs (fixed sweeps) | iccg | mg (multigrid)"),                      \
      ARD_INTEGER(prefix ".iterations", scene.rd.member.max_iterations, 1, 10000, false, \
                  "sweeps, CG iterations, V-cycles or BiCGSTAB steps"),                  \
      ARD_NUMBER(prefix ".tolerance", scene.rd.member.tolerance, 0, 1, false,            \
                 "relative residual to stop at; 0 runs every iteration")
#define ARD_FLOATS(key_, expr, lo, hi, fill_, help_)                                     \
  ParamSpec {                                                                            \
    .key = key_, .kind = ParamKind::kFloats, .min = lo, .max = hi, .choices = {},        \
    .structural = false, .help = help_, .get = nullptr, .set = nullptr, .text = nullptr, \
    .size = nullptr, .floats = [](Preset& p) { return std::span<float>(p.expr); },       \
    .emitters = nullptr, .fill = fill_, .single = true                                   \
  }

const ParamSpec kParams[] = {
    ARD_STRING("name", scene.name, "preset name (defaults to the file name)"),
    ARD_STRING("description", scene.description, "one line for listings"),
    ParamSpec{.key = "grid.size",
              .kind = ParamKind::kSize,
              .min = 4,
              .max = 8192,
              .choices = {},
              .structural = true,
              .help = "[nx, ny] cells",
              .size = [](Preset& p) -> Int2& { return p.scene.size; }},
    ARD_NUMBER("grid.domain_width", scene.domain_width, 1e-6, 1e6, true,
               "domain width; h = domain_width / nx"),
    ARD_NUMBER("grid.dt", scene.dt, 1e-9, 100, false, "time step per frame"),
    ARD_INTEGER("grid.steps", scene.default_steps, 1, 1e9, false,
                "frames for `ardcell run` without --steps"),
    ARD_ENUM("fluid.scene", scene.fluid.kind, kFluidScenes, true,
             "none | cavity | obstacle | ink | table1 (the Table 1 workload, of tile passes)"),
    ARD_NUMBER("fluid.viscosity", scene.fluid.viscosity, 0, 1e3, false, "kinematic viscosity"),
    ARD_NUMBER("fluid.lid_speed", scene.fluid.lid_speed, -1e3, 1e3, false, "cavity lid speed"),
    ARD_NUMBER("fluid.dye_diffusion", scene.fluid.dye_diffusion, 0, 1e3, false,
               "dye diffusion coefficient"),
    ARD_BOOL("fluid.conserve_dye", scene.fluid.conserve_dye, false,
             "put back the dye mass advection loses (closed domains)"),
    ARD_ENUM("fluid.advection", scene.fluid.advection, kAdvection, true,
             "semi-lagrangian (first order) | maccormack (second order, limited)"),
    ARD_NUMBER("fluid.inflow_speed", scene.fluid.inflow_speed, -1e3, 1e3, false,
               "obstacle: inflow speed into the channel (the mean of a parabolic profile)"),
    ARD_ENUM("fluid.inflow_side", scene.fluid.inflow_side, kSides, true,
             "obstacle: left | right | bottom | top; the outflow is the opposite side"),
    ARD_ENUM("fluid.inflow_profile", scene.fluid.inflow_profile, kInflowProfiles, true,
             "obstacle: plug | parabolic (Poiseuille, 1.5x the mean at the middle)"),
    ARD_ENUM("fluid.wall_low", scene.fluid.wall_low, kWalls, true,
             "obstacle: the wall at the low side across the flow (bottom for a flow along x, "
             "left along y): free-slip | no-slip"),
    ARD_ENUM("fluid.wall_high", scene.fluid.wall_high, kWalls, true,
             "obstacle: the wall at the high side across the flow: free-slip | no-slip"),
    ARD_NUMBER("fluid.obstacle_x", scene.fluid.obstacle_x, -1e6, 1e6, true,
               "obstacle: disc centre x (domain units)"),
    ARD_NUMBER("fluid.obstacle_y", scene.fluid.obstacle_y, -1e6, 1e6, true,
               "obstacle: disc centre y (domain units)"),
    ARD_NUMBER("fluid.obstacle_radius", scene.fluid.obstacle_radius, 0, 1e6, true,
               "obstacle: disc radius (domain units)"),
    ARD_ENUM("fluid.obstacle_boundary", scene.fluid.obstacle_boundary, kObstacleBoundaries, true,
             "obstacle: staircase (solid cells) | cut-cell (faces weighed by their open length "
             "in the projection)"),
    ARD_FLOATS("fluid.probes", scene.fluid.probes, 0, 1e6, -1.0,
               "obstacle: up to 4 points [x1, y1, x2, y2, ...] whose velocity and pressure "
               "--probe-csv writes; the first two give the pressure difference"),
    ARD_INTEGER("fluid.inflow_dye_stripes", scene.fluid.inflow_dye_stripes, 0, 4096, false,
                "obstacle: dye stripes entering with the inflow"),
    ARD_ENUM("fluid.walls", scene.fluid.walls, kWalls, true, "ink: free-slip | no-slip | periodic"),
    ParamSpec{
        .key = "fluid.emitters",
        .kind = ParamKind::kEmitters,
        .min = -1e6,
        .max = 1e6,
        .choices = {},
        .structural = false,
        .help = "ink: [[fluid.emitters]] tables of x, y, radius, dye_rate, force_x, "
                "force_y, swirl",
        .emitters = [](Preset& p) -> std::vector<FluidEmitter>& { return p.scene.fluid.emitters; }},
    ARD_SOLVER("fluid.viscosity_solver", viscosity_solver, true),
    ARD_SOLVER("fluid.pressure_solver", pressure_solver, true),
    ARD_BOOL("rd.enabled", scene.rd.enabled, true, "run reaction-diffusion"),
    ARD_BOOL("rd.react", scene.rd.react, true, "false: passive chemicals (advection only)"),
    ARD_BOOL("rd.diffuse", scene.rd.diffuse, true, "diffuse the chemicals"),
    ARD_BOOL("rd.advect", scene.rd.advect, false, "carry the chemicals with the fluid (Eqn 20)"),
    ARD_ENUM("rd.scheme", scene.rd.scheme, kSchemes, true,
             "implicit (Eqns 6, 19) | explicit5 | explicit9 (forward Euler; isotropic only) | "
             "explicit | semi-implicit (generalized operator: seed 003 Eqns 27, 28) | "
             "crank-nicolson-am2 (trapezoidal reaction, Crank-Nicolson diffusion, Strang) | "
             "sbdf2 (BDF2 diffusion, extrapolated reaction) | etdrk4 (exponential RK4 by FFT; "
             "periodic, isotropic)"),
    ARD_NUMBER("rd.dt", scene.rd.dt, 0, 1e6, false, "RD time step; 0: grid.dt"),
    ARD_NUMBER("rd.cell_size", scene.rd.cell_size, 0, 1e6, false,
               "RD cell size h; 0: the grid's h"),
    ARD_INTEGER("rd.steps_per_frame", scene.rd.steps_per_frame, 1, 1000, false,
                "RD steps per frame"),
    ARD_NUMBER("rd.diffusion_a", scene.rd.diffusion_a, 0, 1e6, false, "D_A"),
    ARD_NUMBER("rd.diffusion_b", scene.rd.diffusion_b, 0, 1e6, false, "D_B"),
    ARD_ENUM("rd.boundary", scene.rd.boundary, kBoundaries, true,
             "periodic | neumann | dirichlet (the paper's)"),
    ARD_NUMBER("rd.boundary_a", scene.rd.boundary_a, -1e6, 1e6, false, "Dirichlet value of A"),
    ARD_NUMBER("rd.boundary_b", scene.rd.boundary_b, -1e6, 1e6, false, "Dirichlet value of B"),
    ARD_BOOL("rd.crank_nicolson", scene.rd.crank_nicolson, false,
             "Crank-Nicolson instead of backward Euler diffusion (rd.scheme implicit)"),
    ARD_ENUM("rd.operator", scene.rd.diffusion_operator, kOperators, true,
             "laplacian (Kim & Lin) | generalized (seed 003's 25-point operator; periodic)"),
#define ARD_TENSOR(name, help_) \
  ARD_NUMBER("rd.generalized." #name, scene.rd.generalized.tensors.name, -1e3, 1e3, true, help_)
    ARD_TENSOR(xx, "rank 2: D_xx"),
    ARD_TENSOR(xy, "rank 2: D_xy"),
    ARD_TENSOR(yy, "rank 2: D_yy"),
    ARD_TENSOR(xxx, "rank 3: D_xxx"),
    ARD_TENSOR(xxy, "rank 3: D_xxy"),
    ARD_TENSOR(xyy, "rank 3: D_xyy"),
    ARD_TENSOR(yyy, "rank 3: D_yyy"),
    ARD_TENSOR(xxxx, "rank 4: D_xxxx"),
    ARD_TENSOR(xxxy, "rank 4: D_xxxy"),
    ARD_TENSOR(xxyy, "rank 4: D_xxyy"),
    ARD_TENSOR(xyyy, "rank 4: D_xyyy"),
    ARD_TENSOR(yyyy, "rank 4: D_yyyy"),
#undef ARD_TENSOR
    ARD_INTEGER("rd.generalized.sg_degree", scene.rd.generalized.savitzky_golay_degree, 4, 5, true,
                "Savitzky-Golay fit degree of the rank-3/4 derivatives (5: minimum norm)"),
    ARD_ENUM("rd.generalized.second_derivatives", scene.rd.generalized.second_derivatives,
             kSecondDerivatives, true, "central (the paper's choice) | savitzky-golay"),
    ARD_ENUM("rd.generalized.field", scene.rd.generalized.field, kTensorFields, true,
             "uniform (the sequence) | vortex | radial: a per-cell rank-2 tensor, principal "
             "direction tangential or pointing out from the centre (seed 003 Table 1, last row; "
             "semi-implicit and implicit solve by BiCGSTAB)"),
    ARD_NUMBER("rd.generalized.d_along", scene.rd.generalized.d_along, 0, 1e3, true,
               "rd.generalized.field: the tensor's eigenvalue along its principal direction"),
    ARD_NUMBER("rd.generalized.d_across", scene.rd.generalized.d_across, 0, 1e3, true,
               "rd.generalized.field: the tensor's eigenvalue across it"),
    ARD_RD_SOLVER("rd.diffusion_solver", diffusion_solver),
    ARD_ENUM("rd.reaction.model", scene.rd.reaction.model, kModels, true,
             "gray-scott | turing | meinhardt | fitzhugh-nagumo | barkley | barkley-turbulent"),
    ARD_NUMBER("rd.reaction.f", scene.rd.reaction.F, 0, 1, false, "Gray-Scott feed F"),
    ARD_NUMBER("rd.reaction.k", scene.rd.reaction.k, 0, 1, false, "Gray-Scott kill k"),
    ARD_NUMBER("rd.reaction.turing_s", scene.rd.reaction.turing_s, 0, 1e3, false, "Turing s"),
    ARD_NUMBER("rd.reaction.turing_beta", scene.rd.reaction.turing_beta, -1e3, 1e3, false,
               "Turing beta"),
    ARD_NUMBER("rd.reaction.turing_supply", scene.rd.reaction.turing_supply, 0, 1e3, false,
               "Turing supply of B (Turk's 16; seed 003's beta)"),
    ARD_NUMBER("rd.reaction.meinhardt_s", scene.rd.reaction.meinhardt_s, 0, 1e3, false,
               "Meinhardt s"),
    ARD_NUMBER("rd.reaction.meinhardt_alpha", scene.rd.reaction.meinhardt_alpha, 0, 1e6, false,
               "Meinhardt alpha"),
    ARD_NUMBER("rd.reaction.meinhardt_p1", scene.rd.reaction.meinhardt_p1, -1e3, 0, false,
               "Meinhardt p1 (a decay: <= 0)"),
    ARD_NUMBER("rd.reaction.meinhardt_p2", scene.rd.reaction.meinhardt_p2, -1e3, 0, false,
               "Meinhardt p2 (a decay: <= 0)"),
    ARD_NUMBER("rd.reaction.meinhardt_p3", scene.rd.reaction.meinhardt_p3, 0, 1e3, false,
               "Meinhardt p3 (base production)"),
    ARD_NUMBER("rd.reaction.fhn_epsilon", scene.rd.reaction.fhn_epsilon, 0, 1e3, false,
               "FitzHugh-Nagumo epsilon"),
    ARD_NUMBER("rd.reaction.fhn_a0", scene.rd.reaction.fhn_a0, -1e3, 1e3, false,
               "FitzHugh-Nagumo a0"),
    ARD_NUMBER("rd.reaction.fhn_a1", scene.rd.reaction.fhn_a1, 1e-9, 1e3, false,
               "FitzHugh-Nagumo a1 (> 0)"),
    ARD_NUMBER("rd.reaction.barkley_epsilon", scene.rd.reaction.barkley_epsilon, 1e-9, 1e3, false,
               "Barkley epsilon"),
    ARD_NUMBER("rd.reaction.barkley_a", scene.rd.reaction.barkley_a, 1e-9, 1e3, false, "Barkley a"),
    ARD_NUMBER("rd.reaction.barkley_b", scene.rd.reaction.barkley_b, -1e3, 1e3, false, "Barkley b"),
    ARD_BOOL("rd.map.enabled", scene.rd.map, false,
             "Gray-Scott parameter map (seed 003 Fig. 6): F and k vary across the grid"),
    ARD_NUMBER("rd.map.f_right", scene.rd.map_f, 0, 1, false,
               "map: F at the right edge (rd.reaction.f at the left)"),
    ARD_NUMBER("rd.map.k_top", scene.rd.map_k, 0, 1, false,
               "map: k at the top edge (rd.reaction.k at the bottom)"),
    ARD_BOOL("rd.table.enabled", scene.rd.use_table, true,
             "precomputed implicit reaction table (kernels/reaction_table.h)"),
    ARD_INTEGER("rd.table.resolution", scene.rd.table_resolution, 2, 4096, true,
                "table samples per axis"),
    ARD_BOOL("rd.table.range_auto", scene.rd.table_range_auto, true,
             "true: the model's typical range; false: a_min..b_max"),
    ARD_NUMBER("rd.table.a_min", scene.rd.table_range.a_lo, -1e6, 1e6, true, "table range of A"),
    ARD_NUMBER("rd.table.a_max", scene.rd.table_range.a_hi, -1e6, 1e6, true,
               "table range of A (above a_min)"),
    ARD_NUMBER("rd.table.b_min", scene.rd.table_range.b_lo, -1e6, 1e6, true, "table range of B"),
    ARD_NUMBER("rd.table.b_max", scene.rd.table_range.b_hi, -1e6, 1e6, true,
               "table range of B (above b_min)"),
    ARD_ENUM("rd.anisotropy.kind", scene.rd.anisotropy.kind, kAnisotropies, false,
             "isotropic (Eqn 13) | witkin-kass (Eqn 15) | lobes (Eqn 16) | polar (samples)"),
    ARD_NUMBER("rd.anisotropy.isotropic_value", scene.rd.anisotropy.isotropic_value, 0, 1e3, false,
               "a everywhere (isotropic); scales the explicit schemes' rates"),
    ARD_NUMBER("rd.anisotropy.a1", scene.rd.anisotropy.a1, 0, 1e3, false, "Witkin-Kass a1"),
    ARD_NUMBER("rd.anisotropy.a2", scene.rd.anisotropy.a2, 0, 1e3, false, "Witkin-Kass a2"),
    ARD_INTEGER("rd.anisotropy.lobes", scene.rd.anisotropy.lobes, 1, kMaxLobes, false,
                "lobes j (Eqn 16)"),
    ARD_FLOATS("rd.anisotropy.lobe_speed", scene.rd.anisotropy.lobe_speed, 0, 1e3, 1.0,
               "speed of each lobe, up to 16 (missing: 1)"),
    ARD_INTEGER("rd.anisotropy.samples", scene.rd.anisotropy.samples, 0, kMaxPolarSamples, false,
                "polar samples used; kind polar needs at least 2"),
    ARD_FLOATS("rd.anisotropy.sample", scene.rd.anisotropy.sample, 0, 1e3, 0.0,
               "a at 2 pi i / samples, up to 64 (missing: 0)"),
    ARD_NUMBER("rd.anisotropy.theta0", scene.rd.anisotropy.theta0, -1e3, 1e3, false,
               "orientation theta0 in radians (where no per-cell theta0 is painted)"),
    ARD_BOOL("rd.anisotropy.on_b", scene.rd.anisotropy_on_b, false,
             "true: B diffuses with a(theta) too; false: A only (Eqn 14), B at D_B"),
    ARD_NUMBER("rd.anisotropy.gradient_epsilon", scene.rd.anisotropy.gradient_epsilon, 0, 1, false,
               "gradient below which theta is 0"),
    ARD_ENUM("rd.initial.pattern", scene.rd.initial, kPatterns, false,
             "uniform | centre-square | centre-disc | seed-square | random-spots | stripe"),
    ARD_NUMBER("rd.initial.background_a", scene.rd.background_a, -1e6, 1e6, false,
               "A outside the seed"),
    ARD_NUMBER("rd.initial.background_b", scene.rd.background_b, -1e6, 1e6, false,
               "B outside the seed"),
    ARD_NUMBER("rd.initial.seed_a", scene.rd.seed_a, -1e6, 1e6, false, "A in the seed"),
    ARD_NUMBER("rd.initial.seed_b", scene.rd.seed_b, -1e6, 1e6, false, "B in the seed"),
    ARD_NUMBER("rd.initial.seed_size", scene.rd.seed_size, 0, 1, false,
               "centre-square / stripe: side as a fraction of the width"),
    ARD_INTEGER("rd.initial.seed_cells", scene.rd.seed_cells, 1, 8192, false,
                "seed-square: side in cells"),
    ARD_INTEGER("rd.initial.spots", scene.rd.spots, 0, 1e6, false, "random-spots: count"),
    ARD_NUMBER("rd.initial.seed_radius", scene.rd.seed_radius, 0, 8192, false,
               "random-spots / centre-disc: radius in cells"),
    ARD_NUMBER("rd.initial.noise", scene.rd.noise, 0, 1, false, "relative noise (Pearson: 0.01)"),
    ARD_INTEGER("rd.initial.seed", scene.rd.seed, 0, 9007199254740992.0, false,
                "random seed of the noise and spots"),
    ARD_NAMED("output.show", scene.output.show, kShows, false,
              "field drawn: dye | speed | vorticity | pressure | A | B"),
    ARD_NAMED("output.colormap", scene.output.colormap, kColormaps, false,
              "palette: gray | viridis | magma | rdbu"),
    ARD_BOOL("quality.adaptive", quality.adaptive, false,
             "lower sweeps / RD resolution when a frame would miss"),
    ARD_INTEGER("quality.min_sweeps", quality.min_sweeps, 1, 10000, false,
                "fewest solver sweeps adaptive quality may use"),
    ARD_INTEGER("quality.max_sweeps", quality.max_sweeps, 1, 10000, false,
                "sweeps at full quality (scales every solver's iterations)"),
    ARD_NUMBER("quality.min_rd_scale", quality.min_rd_scale, 0.125, 1, false,
               "lowest RD resolution as a fraction of the grid"),
    ARD_NAMED("input.mode", input.mode, kModes, false,
              "painting mode: deposit | orient | push | obstacle | erase"),
    ARD_NUMBER("input.brush_radius", input.brush_radius, 1e-4, 1, false,
               "brush radius as a fraction of the grid width"),
    ARD_NUMBER("input.strength", input.strength, 0, 1e6, false, "deposit amount / push force"),
    ARD_NUMBER("input.pressure_gamma", input.pressure_gamma, 0.05, 20, false,
               "pressure response: p^gamma"),
};

#undef ARD_RD_SOLVER
#undef ARD_FLOATS
#undef ARD_ACCESS
#undef ARD_NUMBER
#undef ARD_INTEGER
#undef ARD_BOOL
#undef ARD_ENUM
#undef ARD_NAMED
#undef ARD_STRING
#undef ARD_SOLVER

// "1e+02" reads as 100.0; keep TOML floats recognisable as floats.
std::string plain_decimal(std::string s, double v) {
  if (s.find("e+") != std::string::npos && std::abs(v) < 1e15) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.1f", v);
    s = buf;
  }
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s;
}

std::string format_number(double v) {
  char buf[64];
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  std::snprintf(buf, sizeof buf, "%.17g", v);
  std::string s = buf;
  // Shortest form that reads back exactly.
  for (int prec = 1; prec <= 17; ++prec) {
    std::snprintf(buf, sizeof buf, "%.*g", prec, v);
    if (std::strtod(buf, nullptr) == v) {
      s = buf;
      break;
    }
  }
  return plain_decimal(s, v);
}

// The shortest decimal that reads back to the same float.
std::string format_float(float v) {
  if (!std::isfinite(v)) return format_number(v);
  char buf[64];
  std::string s;
  for (int prec = 1; prec <= 9; ++prec) {
    std::snprintf(buf, sizeof buf, "%.*g", prec, double(v));
    if (std::strtof(buf, nullptr) == v) break;
  }
  s = buf;
  return plain_decimal(s, v);
}

// For messages: short and readable ("1e-09", "1000", "0.5").
std::string human_number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

std::string toml_quoted(std::string_view s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      out += buf;
    } else {
      out += c;
    }
  }
  return out + '"';
}

std::string join_choices(std::span<const std::string_view> choices) {
  std::string s;
  for (auto c : choices) {
    if (!s.empty()) s += " | ";
    s += c;
  }
  return s;
}

constexpr std::string_view kEmitterKeys[] = {"x",       "y",       "radius", "dye_rate",
                                             "force_x", "force_y", "swirl"};
double* emitter_field(FluidEmitter& e, std::string_view key) {
  double* fields[] = {&e.x, &e.y, &e.radius, &e.dye_rate, &e.force_x, &e.force_y, &e.swirl};
  for (size_t i = 0; i < std::size(kEmitterKeys); ++i)
    if (kEmitterKeys[i] == key) return fields[i];
  return nullptr;
}

std::string describe_node(const toml::node& n) {
  if (n.is_string()) return "the string " + toml_quoted(*n.value<std::string>());
  if (n.is_integer()) return "the integer " + std::to_string(*n.value<int64_t>());
  if (n.is_floating_point()) return "the number " + human_number(*n.value<double>());
  if (n.is_boolean()) return *n.value<bool>() ? "true" : "false";
  if (n.is_table()) return "a table";
  if (n.is_array()) return "an array";
  return "a date/time";
}

class PresetParser {
 public:
  PresetParser(std::string_view source, Preset& out) : source_(source), out_(out) {}

  void table(const toml::table& t, const std::string& prefix) {
    for (auto&& [k, node] : t) {
      const std::string key =
          prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
      const int line =
          int(k.source().begin.line ? k.source().begin.line : node.source().begin.line);
      const ParamSpec* spec = find_param(key);
      if (!spec) {
        if (node.is_table() && is_section(key)) {
          table(*node.as_table(), key);
          continue;
        }
        error(line, key, unknown_key_hint(key, node.is_table()));
        continue;
      }
      value(*spec, node, line);
    }
  }

  // One value outside a file (`--set key=value`): messages carry no file:line.
  void assign(const ParamSpec& spec, const toml::node& node) { value(spec, node, 0); }

  std::vector<std::string> errors;

 private:
  static bool is_section(const std::string& key) {
    const std::string dotted = key + ".";
    for (const ParamSpec& s : preset_params())
      if (s.key.substr(0, dotted.size()) == dotted) return true;
    return false;
  }

  static std::string unknown_key_hint(const std::string& key, bool is_table) {
    const size_t dot = key.rfind('.');
    const std::string parent = dot == std::string::npos ? "" : key.substr(0, dot);
    std::string known;
    std::vector<std::string> seen;
    for (const ParamSpec& s : preset_params()) {
      std::string_view k = s.key;
      if (!parent.empty()) {
        if (k.substr(0, parent.size() + 1) != parent + ".") continue;
        k.remove_prefix(parent.size() + 1);
      }
      const std::string head(k.substr(0, k.find('.')));
      if (std::find(seen.begin(), seen.end(), head) != seen.end()) continue;
      seen.push_back(head);
      if (!known.empty()) known += ", ";
      known += head;
    }
    return std::string("unknown ") + (is_table ? "table" : "key") + "; expected one of: " + known;
  }

  void error(int line, std::string_view key, const std::string& what) {
    const std::string where =
        source_.empty() ? std::string() : std::string(source_) + ":" + std::to_string(line) + ": ";
    errors.push_back(where + std::string(key) + ": " + what);
  }

  void value(const ParamSpec& spec, const toml::node& node, int line) {
    const std::string expected = "expected " + param_expectation(spec);
    switch (spec.kind) {
      case ParamKind::kNumber: {
        if (!node.is_number())
          return error(line, spec.key, expected + ", got " + describe_node(node));
        const double v = *node.value<double>();
        if (!(v >= spec.min && v <= spec.max))
          return error(line, spec.key, expected + ", got " + human_number(v));
        spec.set(out_, v);
        return;
      }
      case ParamKind::kInteger: {
        if (!node.is_integer())
          return error(line, spec.key, expected + ", got " + describe_node(node));
        const int64_t v = *node.value<int64_t>();
        if (!(double(v) >= spec.min && double(v) <= spec.max))
          return error(line, spec.key, expected + ", got " + std::to_string(v));
        spec.set(out_, double(v));
        return;
      }
      case ParamKind::kBool:
        if (!node.is_boolean())
          return error(line, spec.key, expected + ", got " + describe_node(node));
        spec.set(out_, *node.value<bool>() ? 1.0 : 0.0);
        return;
      case ParamKind::kChoice: {
        if (!node.is_string())
          return error(line, spec.key, expected + ", got " + describe_node(node));
        const std::string s = *node.value<std::string>();
        const double i = choice_index(spec.choices, s);
        if (i < 0) return error(line, spec.key, expected + ", got " + toml_quoted(s));
        spec.set(out_, i);
        return;
      }
      case ParamKind::kString:
        if (!node.is_string())
          return error(line, spec.key, expected + ", got " + describe_node(node));
        spec.text(out_) = *node.value<std::string>();
        return;
      case ParamKind::kSize: {
        const toml::array* a = node.as_array();
        if (!a || a->size() != 2 || !(*a)[0].is_integer() || !(*a)[1].is_integer())
          return error(line, spec.key, expected + ", got " + describe_node(node));
        const int64_t x = *(*a)[0].value<int64_t>(), y = *(*a)[1].value<int64_t>();
        if (!(double(x) >= spec.min && double(x) <= spec.max && double(y) >= spec.min &&
              double(y) <= spec.max))
          return error(line, spec.key,
                       expected + ", got [" + std::to_string(x) + ", " + std::to_string(y) + "]");
        spec.size(out_) = Int2{int(x), int(y)};
        return;
      }
      case ParamKind::kFloats: {
        const toml::array* a = node.as_array();
        const std::span<float> dst = spec.floats(out_);
        if (!a) return error(line, spec.key, expected + ", got " + describe_node(node));
        if (a->size() > dst.size())
          return error(line, spec.key,
                       expected + ", got " + std::to_string(a->size()) + " numbers");
        for (size_t i = 0; i < a->size(); ++i) {
          const toml::node& e = (*a)[i];
          const double v = e.is_number() ? *e.value<double>() : 0.0;
          if (!e.is_number() || !(v >= spec.min && v <= spec.max))
            return error(line, spec.key,
                         expected + ", got " +
                             (e.is_number() ? human_number(v) : describe_node(e)) + " at [" +
                             std::to_string(i) + "]");
        }
        for (size_t i = 0; i < dst.size(); ++i)
          dst[i] = i < a->size() ? float(*(*a)[i].value<double>()) : float(spec.fill);
        return;
      }
      case ParamKind::kEmitters: {
        const toml::array* a = node.as_array();
        if (!a) return error(line, spec.key, expected + ", got " + describe_node(node));
        std::vector<FluidEmitter>& dst = spec.emitters(out_);
        dst.clear();
        for (size_t i = 0; i < a->size(); ++i) {
          const toml::table* t = (*a)[i].as_table();
          const int at = int((*a)[i].source().begin.line ? (*a)[i].source().begin.line : line);
          const std::string where = std::string(spec.key) + "[" + std::to_string(i) + "]";
          if (!t) {
            error(at, where,
                  "expected a table of " + join_choices(kEmitterKeys) + ", got " +
                      describe_node((*a)[i]));
            continue;
          }
          FluidEmitter e;
          for (auto&& [k, v] : *t) {
            double* field = emitter_field(e, k.str());
            const int kl = int(k.source().begin.line ? k.source().begin.line : at);
            if (!field) {
              error(kl, where + "." + std::string(k.str()),
                    "unknown key; expected one of: " + join_choices(kEmitterKeys));
              continue;
            }
            const double x = v.is_number() ? *v.value<double>() : 0.0;
            if (!v.is_number() || !(x >= spec.min && x <= spec.max)) {
              error(kl, where + "." + std::string(k.str()),
                    "expected a number in [" + human_number(spec.min) + ", " +
                        human_number(spec.max) + "], got " +
                        (v.is_number() ? human_number(x) : describe_node(v)));
              continue;
            }
            *field = x;
          }
          dst.push_back(e);
        }
        return;
      }
    }
  }

  std::string_view source_;
  Preset& out_;
};

// A problem of one key given the others (what the engine's rd_config_problem refuses).
struct KeyProblem {
  std::string_view key, depends_on;
  std::string what;
};

std::vector<KeyProblem> scene_key_problems(const SceneConfig& scene) {
  std::vector<KeyProblem> out;
  const RdConfig& rd = scene.rd;
  if (!rd.enabled) return out;
  const auto kind_name = [&] { return kAnisotropies[size_t(rd.anisotropy.kind)]; };
  if (rd.anisotropy.kind == AnisotropyKind::kPolarSamples && rd.anisotropy.samples < 2)
    out.push_back({"rd.anisotropy.samples", "rd.anisotropy.kind",
                   "expected an integer in [2, " + std::to_string(kMaxPolarSamples) +
                       "] with rd.anisotropy.kind polar, got " +
                       std::to_string(rd.anisotropy.samples)});
  const bool anisotropic_scheme = rd.scheme == RdScheme::kImplicit ||
                                  rd.scheme == RdScheme::kCrankNicolsonAm2 ||
                                  rd.scheme == RdScheme::kSbdf2;
  if (!anisotropic_scheme && rd.anisotropy.kind != AnisotropyKind::kIsotropic)
    out.push_back({"rd.scheme", "rd.anisotropy.kind",
                   "expected implicit, crank-nicolson-am2 or sbdf2 with rd.anisotropy.kind " +
                       std::string(kind_name()) +
                       " (the explicit schemes and etdrk4 are isotropic), got " +
                       std::string(kSchemes[size_t(rd.scheme)])});
  if (rd.scheme == RdScheme::kEtdrk4 && rd.boundary != BoundaryKind::kPeriodic)
    out.push_back({"rd.scheme", "rd.boundary",
                   "expected periodic with rd.scheme etdrk4 (its Fourier modes wrap around), got " +
                       std::string(kBoundaries[size_t(rd.boundary)])});
  const bool generalized = rd.diffusion_operator == RdOperator::kGeneralized;
  if (generalized && rd.boundary != BoundaryKind::kPeriodic)
    out.push_back({"rd.boundary", "rd.operator",
                   "expected periodic with rd.operator generalized (its textures tile), got " +
                       std::string(kBoundaries[size_t(rd.boundary)])});
  if (generalized && (rd.scheme == RdScheme::kExplicit5 || rd.scheme == RdScheme::kExplicit9 ||
                      rd.scheme == RdScheme::kCrankNicolsonAm2 || rd.scheme == RdScheme::kSbdf2 ||
                      rd.scheme == RdScheme::kEtdrk4))
    out.push_back({"rd.scheme", "rd.operator",
                   "expected implicit, explicit or semi-implicit with rd.operator generalized, "
                   "got " +
                       std::string(kSchemes[size_t(rd.scheme)])});
  if (!generalized && (rd.scheme == RdScheme::kExplicit || rd.scheme == RdScheme::kSemiImplicit))
    out.push_back({"rd.scheme", "rd.operator",
                   "expected implicit, explicit5, explicit9, crank-nicolson-am2, sbdf2 or etdrk4 "
                   "with rd.operator laplacian, got " +
                       std::string(kSchemes[size_t(rd.scheme)])});
  if (generalized && rd.anisotropy.kind != AnisotropyKind::kIsotropic)
    out.push_back({"rd.anisotropy.kind", "rd.operator",
                   "expected isotropic with rd.operator generalized (the tensor sequence is its "
                   "anisotropy), got " +
                       std::string(kind_name())});
  if (rd.use_table && !rd.table_range_auto) {
    const ConcentrationBox& r = rd.table_range;
    if (!(r.a_hi > r.a_lo))
      out.push_back({"rd.table.a_max", "rd.table.range_auto",
                     "expected more than rd.table.a_min (" + human_number(r.a_lo) + "), got " +
                         human_number(r.a_hi)});
    if (!(r.b_hi > r.b_lo))
      out.push_back({"rd.table.b_max", "rd.table.range_auto",
                     "expected more than rd.table.b_min (" + human_number(r.b_lo) + "), got " +
                         human_number(r.b_hi)});
  }
  return out;
}

std::string file_stem(std::string_view path) {
  const size_t slash = path.rfind('/');
  if (slash != std::string_view::npos) path.remove_prefix(slash + 1);
  const size_t dot = path.rfind('.');
  if (dot != std::string_view::npos && dot > 0) path = path.substr(0, dot);
  return std::string(path);
}

}  // namespace

std::span<const ParamSpec> preset_params() { return kParams; }

const ParamSpec* find_param(std::string_view key) {
  for (const ParamSpec& s : kParams)
    if (s.key == key) return &s;
  return nullptr;
}

std::string param_expectation(const ParamSpec& spec) {
  switch (spec.kind) {
    case ParamKind::kNumber:
      return "a number in [" + human_number(spec.min) + ", " + human_number(spec.max) + "]";
    case ParamKind::kInteger:
      return "an integer in [" + std::to_string(int64_t(spec.min)) + ", " +
             std::to_string(int64_t(spec.max)) + "]";
    case ParamKind::kBool:
      return "true or false";
    case ParamKind::kChoice:
      return "one of " + join_choices(spec.choices);
    case ParamKind::kString:
      return "a string";
    case ParamKind::kSize:
      return "[nx, ny], two integers in [" + std::to_string(int64_t(spec.min)) + ", " +
             std::to_string(int64_t(spec.max)) + "]";
    case ParamKind::kFloats: {
      Preset probe;
      return "an array of at most " + std::to_string(spec.floats(probe).size()) + " numbers in [" +
             human_number(spec.min) + ", " + human_number(spec.max) + "]";
    }
    case ParamKind::kEmitters:
      return "an array of tables of " + join_choices(kEmitterKeys);
  }
  return "?";
}

Status parse_preset(std::string_view text, std::string_view source_name, Preset& out) {
  out = Preset{};
  out.source = std::string(source_name);
  toml::table root;
  try {
    root = toml::parse(text, source_name);
  } catch (const toml::parse_error& e) {
    return Status::error(std::string(source_name) + ":" + std::to_string(e.source().begin.line) +
                         ": " + std::string(e.description()));
  }
  PresetParser parser(source_name, out);
  parser.table(root, "");
  // Cross-key checks, each at the line of its key (else of the first key it depends on).
  if (parser.errors.empty()) {
    std::vector<KeyProblem> problems = scene_key_problems(out.scene);
    if (out.quality.min_sweeps > out.quality.max_sweeps)
      problems.push_back({"quality.min_sweeps", "",
                          "expected at most quality.max_sweeps (" +
                              std::to_string(out.quality.max_sweeps) + "), got " +
                              std::to_string(out.quality.min_sweeps)});
    for (const KeyProblem& p : problems) {
      const toml::node* n = root.at_path(p.key).node();
      if (!n && !p.depends_on.empty()) n = root.at_path(p.depends_on).node();
      const int line = n ? int(n->source().begin.line) : 0;
      parser.errors.push_back(std::string(source_name) + ":" + std::to_string(line) + ": " +
                              std::string(p.key) + ": " + p.what);
    }
  }
  if (!parser.errors.empty()) {
    // In file order (a TOML table iterates its keys by name); the first ones are the lines.
    std::stable_sort(parser.errors.begin(), parser.errors.end(),
                     [n = source_name.size() + 1](const std::string& a, const std::string& b) {
                       return std::atoi(a.c_str() + n) < std::atoi(b.c_str() + n);
                     });
    std::string all;
    for (const std::string& e : parser.errors) {
      if (!all.empty()) all += '\n';
      all += e;
    }
    return Status::error(all);
  }
  if (out.scene.name.empty()) out.scene.name = file_stem(source_name);
  return Status::ok();
}

Status load_preset_file(const std::string& path, Preset& out) {
  std::string text;
  if (Status s = read_user_file(path, kMaxTextConfigBytes, "a preset TOML file", text); !s)
    return s;
  return parse_preset(text, path, out);
}

Status load_preset(std::string_view name_or_path, Preset& out) {
  const bool is_path = name_or_path.find('/') != std::string_view::npos ||
                       (name_or_path.size() > 5 && name_or_path.ends_with(".toml"));
  if (is_path) return load_preset_file(std::string(name_or_path), out);
  if (load_builtin_preset(name_or_path, out)) return Status::ok();
  std::string names;
  for (const std::string& n : preset_names()) names += (names.empty() ? "" : ", ") + n;
  return Status::error("preset '" + std::string(name_or_path) +
                       "': no such file or preset; expected a .toml path or one of: " + names);
}

Status load_builtin_preset(std::string_view name, Preset& out) {
  for (const EmbeddedPreset& e : embedded_presets()) {
    if (file_stem(e.file) == name) {
      Status s = parse_preset(e.text, std::string("presets/") + e.file, out);
      if (s) out.source = "embedded:" + std::string(name);
      return s;
    }
  }
  if (const SceneEntry* entry = builtin_scenes().find(name)) {
    out = preset_from_entry(*entry);
    return Status::ok();
  }
  return Status::error("'" + std::string(name) + "' is not a built-in preset or scene");
}

Preset preset_from_entry(const SceneEntry& entry) {
  Preset p = preset_from_scene(entry.make());
  p.quality = entry.quality;
  return p;
}

Preset preset_from_scene(const SceneConfig& scene) {
  Preset p;
  p.scene = scene;
  p.source = "builtin:" + scene.name;
  // Live input paints as `ardcell run --strokes` does on this scene (fig3-orient: orient).
  p.input.mode = std::string(paint_mode_name(paint_config_for(scene).mode));
  return p;
}

std::string preset_to_toml(const Preset& preset) {
  std::string out = "# ardcell preset (keys: docs/presets.md)\n";
  std::string section;
  Preset& p = const_cast<Preset&>(preset);  // accessors are shared with the setters
  for (const ParamSpec& spec : kParams) {
    const size_t dot = spec.key.rfind('.');
    const std::string table =
        dot == std::string_view::npos ? "" : std::string(spec.key.substr(0, dot));
    const std::string leaf(dot == std::string_view::npos ? spec.key : spec.key.substr(dot + 1));
    if (table != section) {
      out += "\n[" + table + "]\n";
      section = table;
    }
    out += leaf + " = ";
    switch (spec.kind) {
      case ParamKind::kNumber:
        out += spec.single ? format_float(float(spec.get(p))) : format_number(spec.get(p));
        break;
      case ParamKind::kInteger:
        out += std::to_string(int64_t(spec.get(p)));
        break;
      case ParamKind::kBool:
        out += spec.get(p) != 0 ? "true" : "false";
        break;
      case ParamKind::kChoice: {
        const double i = spec.get(p);
        out += i >= 0 && size_t(i) < spec.choices.size()
                   ? toml_quoted(spec.choices[size_t(i)])
                   : toml_quoted(spec.text ? spec.text(p) : "");
        break;
      }
      case ParamKind::kString:
        out += toml_quoted(spec.text(p));
        break;
      case ParamKind::kSize: {
        const Int2 s = spec.size(p);
        out += "[" + std::to_string(s.x) + ", " + std::to_string(s.y) + "]";
        break;
      }
      case ParamKind::kFloats: {
        const std::span<const float> v = spec.floats(p);
        size_t n = v.size();
        while (n > 0 && v[n - 1] == float(spec.fill)) --n;
        out += "[";
        for (size_t i = 0; i < n; ++i) out += (i ? ", " : "") + format_float(v[i]);
        out += "]";
        break;
      }
      case ParamKind::kEmitters: {
        const std::vector<FluidEmitter>& list = spec.emitters(p);
        out += "[";
        for (const FluidEmitter& e : list) {
          FluidEmitter copy = e;
          out += "\n  {";
          for (size_t i = 0; i < std::size(kEmitterKeys); ++i)
            out += std::string(i ? ", " : " ") + std::string(kEmitterKeys[i]) + " = " +
                   format_number(*emitter_field(copy, kEmitterKeys[i]));
          out += " },";
        }
        out += list.empty() ? "]" : "\n]";
        break;
      }
    }
    out += '\n';
  }
  return out;
}

std::string preset_difference(const Preset& a, const Preset& b) {
  Preset& pa = const_cast<Preset&>(a);
  Preset& pb = const_cast<Preset&>(b);
  for (const ParamSpec& spec : kParams) {
    std::string va, vb;
    if (spec.kind == ParamKind::kString) {
      va = spec.text(pa);
      vb = spec.text(pb);
    } else if (spec.kind == ParamKind::kSize) {
      va = std::to_string(spec.size(pa).x) + "x" + std::to_string(spec.size(pa).y);
      vb = std::to_string(spec.size(pb).x) + "x" + std::to_string(spec.size(pb).y);
    } else if (spec.kind == ParamKind::kChoice && spec.text) {
      va = spec.text(pa);
      vb = spec.text(pb);
    } else if (spec.kind == ParamKind::kFloats) {
      const std::span<const float> x = spec.floats(pa), y = spec.floats(pb);
      for (size_t i = 0; i < x.size(); ++i)
        if (x[i] != y[i])
          return std::string(spec.key) + "[" + std::to_string(i) + "]: " + format_float(x[i]) +
                 " vs " + format_float(y[i]);
      continue;
    } else if (spec.kind == ParamKind::kEmitters) {
      std::vector<FluidEmitter>&x = spec.emitters(pa), &y = spec.emitters(pb);
      if (x.size() != y.size())
        return std::string(spec.key) + ": " + std::to_string(x.size()) + " vs " +
               std::to_string(y.size()) + " emitters";
      for (size_t i = 0; i < x.size(); ++i)
        for (std::string_view k : kEmitterKeys)
          if (*emitter_field(x[i], k) != *emitter_field(y[i], k))
            return std::string(spec.key) + "[" + std::to_string(i) + "]." + std::string(k) + ": " +
                   format_number(*emitter_field(x[i], k)) + " vs " +
                   format_number(*emitter_field(y[i], k));
      continue;
    } else {
      const double x = spec.get(a), y = spec.get(b);
      if (x == y || (std::isnan(x) && std::isnan(y))) continue;
      va = format_number(x);
      vb = format_number(y);
    }
    if (va != vb) return std::string(spec.key) + ": " + va + " vs " + vb;
  }
  return {};
}

bool presets_share_structure(const Preset& a, const Preset& b) {
  Preset& pa = const_cast<Preset&>(a);
  Preset& pb = const_cast<Preset&>(b);
  for (const ParamSpec& spec : kParams) {
    if (!spec.structural && spec.kind != ParamKind::kEmitters) continue;
    if (spec.kind == ParamKind::kSize) {
      if (!(spec.size(pa) == spec.size(pb))) return false;
    } else if (spec.kind == ParamKind::kEmitters) {
      // Their values change live; their number is the structure (Engine::update_parameters).
      if (spec.emitters(pa).size() != spec.emitters(pb).size()) return false;
    } else if (spec.kind == ParamKind::kFloats) {
      continue;  // never structural
    } else if (spec.kind == ParamKind::kString) {
      if (spec.text(pa) != spec.text(pb)) return false;
    } else if (spec.get(a) != spec.get(b)) {
      return false;
    }
  }
  return true;
}

Status apply_param_override(SceneConfig& scene, std::string_view assignment) {
  auto trim = [](std::string_view v) {
    while (!v.empty() && (v.front() == ' ' || v.front() == '\t')) v.remove_prefix(1);
    while (!v.empty() && (v.back() == ' ' || v.back() == '\t')) v.remove_suffix(1);
    return v;
  };
  const size_t eq = assignment.find('=');
  if (eq == std::string_view::npos)
    return Status::error("--set " + std::string(assignment) +
                         ": expected key=value, e.g. rd.reaction.f=0.04");
  const std::string key(trim(assignment.substr(0, eq)));
  const std::string_view text = trim(assignment.substr(eq + 1));
  const ParamSpec* spec = find_param(key);
  if (!spec || key.starts_with("quality.") || key.starts_with("input.")) {
    std::string known;
    for (const ParamSpec& s : kParams)
      if (!s.key.starts_with("quality.") && !s.key.starts_with("input.")) {
        if (!known.empty()) known += ", ";
        known += s.key;
      }
    return Status::error("--set " + key + ": unknown scene key; expected one of: " + known);
  }
  if (text.empty())
    return Status::error("--set " + key + ": expected " + param_expectation(*spec) +
                         ", got nothing after '='");
  // The value is TOML; a bare word is a string (choices, names), "256x256" a size.
  std::string value(text);
  if (spec->kind == ParamKind::kSize) {
    const size_t x = value.find('x');
    if (x != std::string::npos && value.front() != '[')
      value = "[" + value.substr(0, x) + ", " + value.substr(x + 1) + "]";
  }
  toml::table doc;
  try {
    doc = toml::parse("v = " + value);
  } catch (const toml::parse_error&) {
    if (spec->kind == ParamKind::kChoice || spec->kind == ParamKind::kString) {
      doc = toml::table{};
      doc.insert("v", std::string(text));
    } else {
      return Status::error("--set " + key + ": expected " + param_expectation(*spec) + ", got '" +
                           std::string(text) + "'");
    }
  }
  Preset edited;
  edited.scene = scene;
  PresetParser parser("", edited);
  parser.assign(*spec, *doc.get("v"));
  if (!parser.errors.empty()) return Status::error("--set " + parser.errors.front());
  scene = std::move(edited.scene);
  return Status::ok();
}

Status check_scene_keys(const SceneConfig& scene) {
  std::string all;
  for (const KeyProblem& p : scene_key_problems(scene))
    all += (all.empty() ? "" : "\n") + std::string(p.key) + ": " + p.what;
  return all.empty() ? Status::ok() : Status::error(all);
}

bool set_param(Preset& preset, const ParamSpec& spec, double value, std::string* why) {
  if (!spec.set) {
    if (why) *why = std::string(spec.key) + ": cannot be set live (expected a numeric key)";
    return false;
  }
  if (spec.kind == ParamKind::kInteger || spec.kind == ParamKind::kChoice)
    value = std::round(value);
  if (!(value >= spec.min && value <= spec.max)) {
    if (why)
      *why = std::string(spec.key) + ": expected " + param_expectation(spec) + ", got " +
             human_number(value);
    return false;
  }
  spec.set(preset, value);
  return true;
}

Status check_flag_param(std::string_view key, double value, std::string_view flag) {
  const ParamSpec* spec = find_param(key);
  if (!spec) return Status::error(std::string(flag) + ": unknown preset key " + std::string(key));
  if (spec->kind == ParamKind::kInteger || spec->kind == ParamKind::kSize)
    value = std::isfinite(value) && value == std::round(value) ? value : NAN;
  if (value >= spec->min && value <= spec->max) return Status::ok();
  return Status::error(std::string(flag) + " " + human_number(value) + ": expected " +
                       param_expectation(*spec) + " (preset key " + std::string(key) + ")");
}

Status set_flag_param(Preset& preset, std::string_view key, double value, std::string_view flag) {
  if (Status s = check_flag_param(key, value, flag); !s) return s;
  const ParamSpec* spec = find_param(key);
  if (!spec->set)
    return Status::error(std::string(flag) + ": preset key " + std::string(key) +
                         " is not a number");
  spec->set(preset, value);
  return Status::ok();
}

double get_param(const Preset& preset, const ParamSpec& spec) {
  return spec.get ? spec.get(preset) : 0.0;
}

void blend_params(const Preset& from, const Preset& to, double t, Preset& out) {
  t = std::clamp(t, 0.0, 1.0);
  Preset& pf = const_cast<Preset&>(from);
  Preset& pt = const_cast<Preset&>(to);
  for (const ParamSpec& spec : kParams) {
    if (spec.kind == ParamKind::kFloats) {
      const std::span<const float> a = spec.floats(pf), b = spec.floats(pt);
      const std::span<float> o = spec.floats(out);
      for (size_t i = 0; i < o.size(); ++i) o[i] = float(a[i] + (b[i] - a[i]) * t);
      continue;
    }
    if (!spec.set || spec.structural) continue;
    const double a = spec.get(from), b = spec.get(to);
    double v = b;
    if (spec.kind == ParamKind::kNumber)
      v = a + (b - a) * t;
    else if (spec.kind == ParamKind::kInteger)
      v = std::round(a + (b - a) * t);
    else
      v = t >= 0.5 ? b : a;
    if (spec.kind == ParamKind::kChoice && v < 0) continue;
    if (spec.get(out) != v) spec.set(out, v);
  }
}

void apply_quality(const Preset& preset, const QualityLevel& level, SceneConfig& out) {
  const double f = preset.quality.max_sweeps > 0
                       ? std::clamp(double(level.sweeps) / preset.quality.max_sweeps, 0.0, 1.0)
                       : 1.0;
  auto scaled = [f](int iterations) { return std::max(1, int(std::lround(iterations * f))); };
  out.fluid.pressure_solver.max_iterations =
      scaled(preset.scene.fluid.pressure_solver.max_iterations);
  out.fluid.viscosity_solver.max_iterations =
      scaled(preset.scene.fluid.viscosity_solver.max_iterations);
  out.rd.diffusion_solver.max_iterations = scaled(preset.scene.rd.diffusion_solver.max_iterations);
}

void use_realtime_solvers(Preset& preset) {
  set_fluid_solver(preset.scene.fluid, SolverKind::kJacobi, preset.quality.max_sweeps);
  preset.scene.rd.diffusion_solver = preset.scene.fluid.pressure_solver;
  // The Table 1 plan reacts by Newton in its passes (host/engine/table1_plan.h): no table.
  if (preset.scene.rd.scheme == RdScheme::kImplicit &&
      preset.scene.fluid.kind != FluidSceneKind::kTable1)
    preset.scene.rd.use_table = true;
}

std::vector<std::string> preset_names() {
  std::vector<std::string> names;
  for (const EmbeddedPreset& e : embedded_presets()) names.push_back(file_stem(e.file));
  std::sort(names.begin(), names.end());
  for (const SceneEntry& s : builtin_scenes().entries())
    if (std::find(names.begin(), names.end(), s.name) == names.end()) names.push_back(s.name);
  return names;
}

}  // namespace ardcell
