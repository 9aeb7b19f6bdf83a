// Every built-in preset on every CPU back end: the threads back end with 1, 2 and 4 workers
// must give the serial reference's fields bit for bit after 50 frames, at a size no tiling
// divides evenly (127 x 93). Reductions (residual norms, the dye's mass fix) add per-row
// partials in row order, and each row is written by one band, so nothing may differ.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "host/engine/engine.h"
#include "host/scenes/preset.h"
#include "runtime/row_executor.h"
#include "tests/support/preset_params.h"

namespace ardcell {
namespace {

constexpr int kFrames = 50;

// The first cell (field, x, y) where a and b differ in any bit, or "" when none does.
std::string first_difference(const SimState& a, const SimState& b) {
  std::vector<std::pair<std::string_view, const FieldF*>> fa, fb;
  a.for_each_field([&](std::string_view n, const FieldF& f) { fa.emplace_back(n, &f); });
  b.for_each_field([&](std::string_view n, const FieldF& f) { fb.emplace_back(n, &f); });
  if (fa.size() != fb.size()) return "different sets of fields";
  for (std::size_t k = 0; k < fa.size(); ++k) {
    const FieldF &f = *fa[k].second, &g = *fb[k].second;
    for (int y = 0; y < f.ny(); ++y)
      for (int x = 0; x < f.nx(); ++x)
        if (std::memcmp(&f(x, y), &g(x, y), sizeof(float)) != 0)
          return std::string(fa[k].first) + " at (" + std::to_string(x) + ", " + std::to_string(y) +
                 "): " + std::to_string(f(x, y)) + " vs " + std::to_string(g(x, y));
  }
  return "";
}

void expect_threads_equal_serial(const SceneConfig& scene, const std::string& what) {
  ASSERT_GT(long(scene.size.x) * scene.size.y, RowExecutor::kMinParallelCells)
      << "the grid must be large enough for the threads back end to cut it into bands";
  Engine serial(scene, {EngineOptions::Backend::kSerial, 1});
  for (int k = 0; k < kFrames; ++k) serial.step();
  for (int workers : {1, 2, 4}) {
    Engine threads(scene, {EngineOptions::Backend::kThreads, workers});
    ASSERT_EQ(threads.workers(), workers);
    for (int k = 0; k < kFrames; ++k) threads.step();
    EXPECT_EQ(first_difference(serial.state(), threads.state()), "")
        << what << " with " << workers << " workers";
  }
}

class EngineBackendParity : public testing::TestWithParam<std::string> {};

TEST_P(EngineBackendParity, ThreadsEqualSerialBitForBit) {
  SceneConfig scene = awkward_preset_scene(GetParam());
  // At most 10 RD steps a frame (as the McGraw presets take): mcgraw-turing-vortex's 100 would
  // spend a minute under the sanitizers repeating the same per-step work 50 000 times. A tensor
  // field's BiCGSTAB solves (mcgraw-turing-radial: some 60 passes over the fields a step) take
  // 2: 100 steps of every op (with 10 the test took four minutes under the sanitizers).
  const bool krylov = scene.rd.generalized.field != TensorFieldKind::kUniform &&
                      scene.rd.scheme != RdScheme::kExplicit;
  scene.rd.steps_per_frame = std::min(scene.rd.steps_per_frame, krylov ? 2 : 10);
  expect_threads_equal_serial(scene, GetParam());
}

// MacCormack advection of the velocity, the dye and the chemicals (only `ink` uses it among
// the presets, and it has no chemicals).
TEST(EngineBackendParity, MacCormackAdvectionOfChemicalsThreadsEqualSerial) {
  SceneConfig scene = awkward_preset_scene("obstacle-ard-gray-scott");
  scene.fluid.advection = AdvectionScheme::kMacCormack;
  expect_threads_equal_serial(scene, "obstacle-ard-gray-scott with MacCormack advection");
}

INSTANTIATE_TEST_SUITE_P(EveryPreset, EngineBackendParity, testing::ValuesIn(preset_names()),
                         preset_test_name);

}  // namespace
}  // namespace ardcell
