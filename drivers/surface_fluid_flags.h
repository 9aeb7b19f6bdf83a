#pragma once
// The stable-fluids flags `ardcell surface` and `ardcell live` share (--fluid, --force,
// --conserve-dye): one meaning, one parser, one set of refusals. The values are checked where
// they are used (parse_fluid_force, host/surface/surface_scene.h), since a build without
// OpenSubdiv has no surface to run them on.
#include <string>

#include "drivers/cli.h"

namespace ardcell {

struct SurfaceFluidFlags {
  std::string fluid;  // gravity | walk
  double force = 1;
  bool conserve_dye = false;
  CLI::Option* fluid_opt = nullptr;
  CLI::Option* force_opt = nullptr;
  CLI::Option* conserve_dye_opt = nullptr;
  // --force or --conserve-dye given, the first of them, else null.
  CLI::Option* setting_given() const;
};

// Adds --fluid (with `fluid_help`), --force and --conserve-dye (its help ending with
// `conserve_dye_default`) to `cmd`, into `flags`.
void add_surface_fluid_flags(CLI::App& cmd, SurfaceFluidFlags& flags, const std::string& fluid_help,
                             const std::string& conserve_dye_default = "");

// A flag's value, when one is given (--flag=VALUE): true or false, 1 or 0, nothing else (CLI11
// would read any number as a bool).
const CLI::Validator& flag_value();

// The line refusing a fluid setting without --fluid: "--force: a fluid setting (expected --fluid
// gravity or walk)".
std::string fluid_setting_without_fluid(const CLI::Option& option);

}  // namespace ardcell
