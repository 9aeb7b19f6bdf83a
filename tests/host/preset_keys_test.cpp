// The preset key table covers every SceneConfig field, and `--set key=value` overrides.
#include <gtest/gtest.h>

#include "host/preset.h"
#include "host/scene_registry.h"

namespace ardcell {
namespace {

TEST(ParamOverride, SetsNumbersChoicesSizesAndStrings) {
  SceneConfig s;
  ASSERT_TRUE(apply_param_override(s, "fluid.viscosity=0.02").is_ok());
  EXPECT_EQ(s.fluid.viscosity, 0.02);
  ASSERT_TRUE(apply_param_override(s, " fluid.pressure_solver.kind = rbgs ").is_ok());
  EXPECT_EQ(s.fluid.pressure_solver.kind, SolverKind::kRedBlackGaussSeidel);
  ASSERT_TRUE(apply_param_override(s, "fluid.pressure_solver.kind=\"iccg\"").is_ok());
  EXPECT_EQ(s.fluid.pressure_solver.kind, SolverKind::kIccg);
  ASSERT_TRUE(apply_param_override(s, "grid.size=64x32").is_ok());
  EXPECT_EQ(s.size, (Int2{64, 32}));
  ASSERT_TRUE(apply_param_override(s, "grid.size=[16, 8]").is_ok());
  EXPECT_EQ(s.size, (Int2{16, 8}));
  ASSERT_TRUE(apply_param_override(s, "description=a quick look").is_ok());
  EXPECT_EQ(s.description, "a quick look");
}

TEST(ParamOverride, BadAssignmentsNameTheKeyAndLeaveTheSceneAlone) {
  SceneConfig s;
  const SceneConfig before = s;
  auto fails = [&](std::string_view a, std::string_view expected) {
    const Status st = apply_param_override(s, a);
    ASSERT_FALSE(st.is_ok()) << a;
    EXPECT_EQ(st.message(), expected) << a;
    EXPECT_EQ(st.message().find('\n'), std::string::npos);
  };
  fails("fluid.viscosity=-1", "--set fluid.viscosity: expected a number in [0, 1000], got -1");
  fails("fluid.viscosity=abc", "--set fluid.viscosity: expected a number in [0, 1000], got 'abc'");
  fails("fluid.viscosity", "--set fluid.viscosity: expected key=value, e.g. rd.reaction.f=0.04");
  fails("fluid.viscosity=",
        "--set fluid.viscosity: expected a number in [0, 1000], got nothing after '='");
  fails("fluid.pressure_solver.kind=sor",
        "--set fluid.pressure_solver.kind: expected one of jacobi | rbgs | iccg | mg, got \"sor\"");
  const Status unknown = apply_param_override(s, "fluid.viscosty=1");
  ASSERT_FALSE(unknown.is_ok());
  EXPECT_TRUE(
      unknown.message().starts_with("--set fluid.viscosty: unknown scene key; expected one of: "))
      << unknown.message();
  EXPECT_FALSE(apply_param_override(s, "quality.max_sweeps=3").is_ok());
  EXPECT_EQ(s.fluid.viscosity, before.fluid.viscosity);
  EXPECT_EQ(s.fluid.pressure_solver.kind, before.fluid.pressure_solver.kind);
}

}  // namespace
}  // namespace ardcell
