#include "drivers/surface_fluid_flags.h"

namespace ardcell {

CLI::Option* SurfaceFluidFlags::setting_given() const {
  for (CLI::Option* o : {force_opt, conserve_dye_opt})
    if (o && o->count()) return o;
  return nullptr;
}

const CLI::Validator& flag_value() {
  static const CLI::Validator validator(
      [](std::string& value) -> std::string {
        for (const char* ok : {"", "true", "false", "1", "0"})
          if (value == ok) return {};
        return "expected no value, true or false, got '" + value + "'";
      },
      "", "flag");
  return validator;
}

void add_surface_fluid_flags(CLI::App& cmd, SurfaceFluidFlags& flags, const std::string& fluid_help,
                             const std::string& conserve_dye_default) {
  flags.fluid_opt = cmd.add_option("--fluid", flags.fluid, fluid_help);
  flags.force_opt =
      cmd.add_option("--force", flags.force,
                     "--fluid: gravity's acceleration per unit dye, or the walkers' push (1)")
          ->check(finite_range(0, 1e6));
  flags.conserve_dye_opt =
      cmd.add_flag("--conserve-dye", flags.conserve_dye,
                   "--fluid: each advection keeps the dye's total, the dye within [0, 1] "
                   "(advection alone drifts)" +
                       conserve_dye_default)
          ->check(flag_value());
}

std::string fluid_setting_without_fluid(const CLI::Option& option) {
  return option.get_name() + ": a fluid setting (expected --fluid gravity or walk)";
}

}  // namespace ardcell
