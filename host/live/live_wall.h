#pragma once
// One screen of a video wall (`mpirun -np N ardcell live PRESET --wall WxH`): N processes show
// one simulation, each its part of the grid in a window of its own, on its own display. Who
// computes what depends on the scene:
//   split    - a scene that runs as blocks (host/engine/engine.h block_support: the table1
//              scenes, the explicit RD schemes without a fluid; not those whose blocks gather
//              the grid, BlockSupport::gathers): each screen runs its block of the grid
//              (runtime/block_layout.h), the halo exchange between them;
//   mirrored - every other scene (its solves or its fluid run on the gathered grid, so a block
//              would compute the whole grid anyway): every screen steps the
//              whole grid in lockstep and shows its part. The screens' inputs are the same, so
//              on the same binary and CPU they compute the same bits; on different CPUs or
//              GPUs rounding may differ, so every kCheckFrames frames the screens compare a
//              fingerprint of their state and, when one differs from screen 0's, screen 0's
//              state is sent to every screen (the loop says so in one line).
// Every frame the live loop (host/live/live_loop.h) hands the wall this screen's input and gets
// every screen's back, screen by screen, so that a stroke, a key, an OSC or a GPIO command on
// any screen acts on every screen in the same frame; the screens agree on the shown field's
// range, and each waits for all before presenting, so they show the same frame.
// host/live/rank_wall.h is the wall over Open MPI; tests use an in-process one.
#include <array>
#include <cstdint>
#include <span>
#include <string_view>

#include "host/config/sim_state.h"
#include "host/live/live_loop.h"
#include "runtime/block_layout.h"
#include "runtime/field.h"

namespace ardcell {

// One screen's input of one frame: plain data, exchanged as bytes.
struct WallInput {
  static constexpr int kMaxSamples = 64;
  static constexpr int kMaxCommands = 8;
  int samples = 0, commands = 0;
  bool stop = false;      // a signal asked this process to stop: every screen quits
  bool activity = false;  // someone used this screen's input (the attract mode's idle clock)
  // This screen's preset switch has loaded and built (ok: without error; digest: the preset's
  // text_fingerprint). A mirrored wall switches in the frame where every screen's has, and only
  // when every screen's is ok and every screen loaded the same preset.
  bool build_done = false, build_ok = false;
  std::uint64_t build_digest = 0;
  std::array<StrokeSample, kMaxSamples> sample{};  // normalised to the whole grid
  std::array<LiveCommand, kMaxCommands> command{};
};

class LiveWall {
 public:
  // Frames between two comparisons of a mirrored wall's states (a second at 60 Hz).
  static constexpr int kCheckFrames = 60;

  virtual ~LiveWall() = default;
  virtual int screens() const = 0;
  virtual int screen() const = 0;  // this one: 0 .. screens() - 1
  virtual Int2 grid() const = 0;
  // The cells this screen computes (its block; the whole grid on a mirrored wall) and the cells
  // it shows: its part of the wall less the bezel's cells at its inner edges, so that a line
  // crossing screens stays straight across the gap between them.
  virtual Box2 block() const = 0;
  virtual Box2 view() const = 0;
  // Every screen steps the whole grid (block() is the grid), or each its block.
  virtual bool mirrored() const = 0;
  // Every screen's input, in screen order (all screens call it together, once a frame).
  virtual std::span<const WallInput> share(const WallInput& mine) = 0;
  // The least lo and greatest hi over the screens (all screens call it together).
  virtual void agree_range(float& lo, float& hi) = 0;
  // Returns when every screen is ready to present its frame.
  virtual void before_present() = 0;
  // Every screen's image of its view, placed as the views lie on the grid (image rows top down,
  // the bezels black), in `wall` on screen 0, which returns true; the others return false. All
  // screens call it together, each image at the same number of pixels per cell (the live loop's
  // frames: one).
  virtual bool gather_image(const ImageRgb8& mine, ImageRgb8& wall) = 0;
  // A mirrored wall's check (all screens call it together): the first screen whose state's
  // fingerprint (state_fingerprint) differs from screen 0's, or -1 when all agree.
  virtual int first_drifted(std::uint64_t fingerprint) = 0;
  // Screen 0's fields (their interior cells; the obstacle mask too), time and step into `state`
  // on every screen (all screens call it together, each with a state of the same preset: the
  // same fields and sizes; halos may differ).
  virtual void send_state(SimState& state) = 0;
  // A mirrored wall switching presets: the views over a grid of `grid` cells from now on; false
  // (nothing changes) when a view would keep no cell, or on a split wall unless the grid is the
  // same (its blocks are cut for one grid).
  virtual bool regrid(Int2 grid) = 0;
};

// A fingerprint of every field's interior cells (their bits; the obstacle mask's too) and the
// step: equal states give equal fingerprints, and states that differ in any cell almost surely
// do not. Halos are left out (their width may differ between back ends). No allocation.
std::uint64_t state_fingerprint(const SimState& state);
// A fingerprint of `text` (FNV-1a, 64 bits): the screens compare the presets they load as
// preset_to_toml text.
std::uint64_t text_fingerprint(std::string_view text);

// The cells screen `b` of a wall laid out as `layout` shows: its block less `bezel_cells` cells
// across each gap between screens (the left / lower screen hides half, the other the rest).
Box2 wall_view(const BlockLayout& layout, int b, int bezel_cells);
// Places `image` (a view's pixels, `scale` per cell, top row first) where `view` lies on a grid
// of `grid` cells, in `wall` (grid * scale pixels, top row the grid's highest y).
void place_on_wall(const ImageRgb8& image, Box2 view, Int2 grid, int scale, ImageRgb8& wall);

}  // namespace ardcell
