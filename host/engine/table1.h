#pragma once
// The Table 1 workload of seed 000 (section 7.2): Stam's stable fluid on an N x N grid, alone
// ("fluid") or with Gray-Scott reaction-diffusion riding on it ("ard"), under one of three
// schedules of the same kernels:
//   serial  - whole-grid reference: every stage a global loop (SerialBackend), no tiling;
//   stream  - Cell-faithful: every solver sweep streams the tiles through the local stores
//             (threads back end); the RD work is fused into passes the fluid makes anyway
//             (reaction with the sources pass, A's and B's 20 diffusion sweeps in store with
//             the projections' divergence passes, their advection with the dye's);
//   blocked - ghost-zone temporal blocking: each 20-sweep solve loads its tile with halo 20
//             once, sweeps in store and writes the core once; the projection (divergence,
//             solve, gradient) is one pass.
// All three give the same fields bit for bit (tests/host/engine/tiling_parity_test.cpp). The exact
// definition of the frame is in bench/README.md.
#include <cstdint>
#include <memory>
#include <span>
#include <string_view>

#include "host/engine/frame_plan.h"
#include "kernels/advect.h"
#include "kernels/project.h"
#include "kernels/reaction.h"
#include "kernels/stam_sweeps.h"
#include "runtime/backend.h"

namespace ardcell {

enum class Table1Schedule : uint8_t { kSerial, kStream, kBlocked };

// "serial", "stream", "blocked"; false when unknown.
bool parse_table1_schedule(std::string_view name, Table1Schedule& out);
std::string_view table1_schedule_name(Table1Schedule s);

struct Table1Options {
  int n = 128;      // grid is n x n interior cells
  bool rd = false;  // fluid + Gray-Scott RD
  Table1Schedule schedule = Table1Schedule::kStream;
  int workers = 0;  // threads back end workers (0: one per hardware thread)
  std::size_t local_store_bytes = machine_local_store_bytes();
  int sweeps_per_residency = 20;  // blocked: sweeps per tile load (20 = one load per solve)
  int max_tile_width = 0;         // test hooks: cap tile sizes to force awkward tilings
  int max_tile_height = 0;
  Int2 grid{};  // when non-zero, a non-square grid (tests: 127 x 93); n is then ignored
  // Inject a custom back end (OpenCL): not owned; null = serial or threads per schedule.
  Backend* backend = nullptr;
};

// The constants of the workload (bench/README.md).
struct Table1Constants {
  static constexpr int kSweeps = 20;
  static constexpr float kDt = 0.1f;
  static constexpr float kViscosity = 1e-4f;
  static constexpr float kDyeDiffusion = 1e-4f;
  static constexpr float kGrayScottF = 0.055f, kGrayScottK = 0.062f;
  static constexpr float kRdStep = 1.0f;                // RD time per frame, in Gray-Scott units
  static constexpr float kDiffA = 1.0f, kDiffB = 0.5f;  // cells^2 per RD time unit
  static constexpr int kSplats = 4;
  // Bytes per cell per frame a sweep-by-sweep implementation must move (each stage reads its
  // inputs once and writes its outputs once, float32); the bytes_per_s counter's numerator.
  static constexpr double kFluidBytesPerCell = 1328;
  static constexpr double kRdBytesPerCell = 520;
};

class Table1Workload {
 public:
  explicit Table1Workload(const Table1Options& options);
  ~Table1Workload();
  Table1Workload(const Table1Workload&) = delete;
  Table1Workload& operator=(const Table1Workload&) = delete;

  // Back to the initial conditions, frame 0.
  void reset();
  // One frame (no heap allocation).
  void step();

  std::int64_t frame() const { return frame_; }
  Int2 grid() const { return grid_; }
  const Table1Options& options() const { return options_; }
  const FieldF& u() const;
  const FieldF& v() const;
  const FieldF& dye() const;
  const FieldF& a() const;  // RD chemicals (allocated only with rd)
  const FieldF& b() const;

  double bytes_per_frame() const;  // sweep-by-sweep minimum traffic of one frame
  FramePlan& plan() { return *plan_; }
  Backend& backend() { return *backend_; }

 private:
  struct Fields;
  struct Params;
  void build();
  void add_sources_pass(bool with_reaction);
  struct DiffusionSpec {
    FieldF* x;    // initial guess and right-hand side (kept)
    FieldF* out;  // result
    FieldF* tmp;  // ping-pong partner of out
    const StamSweepParams* params;
    int b;  // Stam's set_bnd kind
  };
  void add_diffusion(const char* name, std::span<const DiffusionSpec> solves, bool with_sources);
  void append_residency(PassDesc& d, const DiffusionSpec& sv, const FieldF* cur, FieldF* next,
                        int sweeps, bool whole, bool with_sources);
  void add_projection(const char* name, FieldF& u, FieldF& v, FieldF& u_out, FieldF& v_out,
                      int pressure_pass_with_rider);
  void add_rd_diffusion_pass();

  Table1Options options_;
  Int2 grid_{};
  std::int64_t frame_ = 0;
  std::unique_ptr<Fields> f_;
  std::unique_ptr<Params> p_;
  std::unique_ptr<FramePlan> plan_;
  std::unique_ptr<Backend> owned_backend_;
  Backend* backend_ = nullptr;
};

}  // namespace ardcell
