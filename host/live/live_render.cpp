// The live loop's image of a frame: the shown field through its colormap (on a wall, this
// screen's view in the range the screens agree on), and the crossfade of a preset switch.
#include "host/live/live_loop.h"

#include <algorithm>
#include <cmath>

#include "host/live/live_wall.h"
#include "host/render/frame_render.h"

namespace ardcell {

namespace {
// The field's usual settings with the preset's colormap (unless the field needs a diverging one).
RenderSettings output_render_settings(FrameField field, const OutputConfig& output) {
  RenderSettings settings = default_render_settings(field);
  Colormap map;
  if (parse_colormap(output.colormap, map) && !colormap_is_diverging(settings.colormap))
    settings.colormap = map;
  return settings;
}
}  // namespace

void render_state(const SimState& state, const OutputConfig& output, ImageRgb8& out) {
  render_frame(state, output_render_settings(shown_frame_field(state, output.show), output), out);
}

void crossfade_images(const ImageRgb8& from, double t, ImageRgb8& to) {
  if (from.empty() || to.empty()) return;
  const int w = std::clamp(int(std::lround(t * 256.0)), 0, 256);
  for (int y = 0; y < to.height; ++y) {
    const uint8_t* src = from.row(int(int64_t(y) * from.height / to.height));
    uint8_t* dst = to.row(y);
    for (int x = 0; x < to.width; ++x) {
      const uint8_t* s = src + size_t(int64_t(x) * from.width / to.width) * 3;
      for (int c = 0; c < 3; ++c)
        dst[3 * x + c] = uint8_t((dst[3 * x + c] * w + s[c] * (256 - w) + 128) >> 8);
    }
  }
}

// Only what the shown field is drawn from comes to the host (on OpenCL: one or two fields a
// frame, not the whole state).
void LiveLoop::render() {
  if (const Int2 view = sim_->view_size(); view.x > 0 && view.y > 0) {
    sim_->render(image_);
    return;
  }
  if (!options_.wall) {
    const FrameField shown = shown_frame_field(sim_->state({}), preset_.scene.output.show);
    render_state(sim_->state(frame_field_inputs(shown)), preset_.scene.output, image_);
    return;
  }
  // A wall's screen draws its view in the range of the whole grid, as one process would: an
  // automatic range from every screen's block.
  LiveWall& wall = *options_.wall;
  const Box2 block = wall.block();
  const FrameField shown = shown_frame_field(sim_->state({}), preset_.scene.output.show, block);
  const SimState& state = sim_->state(frame_field_inputs(shown));
  RenderSettings settings = output_render_settings(shown, preset_.scene.output);
  if (settings.range != RangeMode::kFixed) {
    FieldValueRange values = frame_value_range(state, shown, block);
    float least_abs = -values.abs_max;
    wall.agree_range(values.lo, values.hi);
    wall.agree_range(least_abs, values.abs_max);
    range_limits(settings.range, values, settings.lo, settings.hi);
    settings.range = RangeMode::kFixed;
  }
  render_frame(state, settings, image_, wall.view());
}

}  // namespace ardcell
