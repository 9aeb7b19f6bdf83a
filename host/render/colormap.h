#pragma once
// Colormaps for frames: grayscale, two perceptually uniform maps (viridis and magma, the
// published 256-entry tables of van der Walt and Smith, as shipped in matplotlib), and a
// diverging map for signed fields such as vorticity (ColorBrewer RdBu, blue for negative, white
// at zero, red for positive). Non-finite values get one fixed colour so a NaN never reaches the
// screen as an arbitrary pixel.
#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <string_view>

namespace ardcell {

struct Rgb8 {
  uint8_t r = 0, g = 0, b = 0;
  friend constexpr bool operator==(Rgb8, Rgb8) = default;
};

enum class Colormap : uint8_t { kGray, kViridis, kMagma, kRdBu };

// Drawn for NaN and +-inf (magenta: in none of the maps, so it stands out).
inline constexpr Rgb8 kNonFiniteRgb{255, 0, 255};

// "gray", "viridis", "magma", "rdbu"; false when the name is unknown.
bool parse_colormap(std::string_view name, Colormap& out);
std::string_view colormap_name(Colormap map);
// Every map name, for --help and error messages ("gray|viridis|magma|rdbu").
std::string_view colormap_names();
// True for maps centred on a middle value (rdbu): signed fields map 0 to the centre.
bool colormap_is_diverging(Colormap map);

// The map as 256 RGB8 entries, entry 0 for the low end.
const std::array<Rgb8, 256>& colormap_lut(Colormap map);

// The published float table behind a tabulated map (viridis, magma): 256 rows of r, g, b in
// [0, 1]. Empty for maps that are computed (gray, rdbu).
std::span<const std::array<float, 3>> colormap_source_table(Colormap map);

// t in [0, 1] (clamped) to a colour; NaN and +-inf give kNonFiniteRgb.
inline Rgb8 colormap_at(const std::array<Rgb8, 256>& lut, float t) {
  if (!std::isfinite(t)) return kNonFiniteRgb;
  t = t < 0.0f ? 0.0f : (t > 1.0f ? 1.0f : t);
  return lut[static_cast<int>(t * 255.0f + 0.5f)];
}

}  // namespace ardcell
