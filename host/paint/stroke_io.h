#pragma once
// The stroke recording format (".jsonl"): one JSON object per sample per line, e.g.
//   {"t":0.016,"x":0.5,"y":0.25,"pressure":0.8,"tilt_x":0,"tilt_y":0,"buttons":1,
//    "in_range":true,"eraser":false}
// t is seconds, x/y normalized to [0, 1] (host/paint/stroke.h), pressure 0..1, tilt in degrees,
// buttons the StrokeButton bits (1 = tip). Only "t", "x" and "y" are required; missing keys
// take StrokeSample's defaults except in_range, which defaults to true. Blank lines and lines
// starting with '#' are skipped. Times must not decrease. Used by the kiosk attract mode,
// `ardcell run --strokes FILE` and the tests.
#include <string>
#include <string_view>
#include <vector>

#include "host/paint/stroke.h"

namespace ardcell {

// One line of JSON for s (no newline).
std::string stroke_sample_to_json(const StrokeSample& s);
// Parses one line; false with `error` set (what was wrong, what was expected) on bad input.
bool stroke_sample_from_json(std::string_view line, StrokeSample& out, std::string& error);

// Reads a whole file; false with a one-line `error` that names the file and line.
bool read_stroke_file(const std::string& path, std::vector<StrokeSample>& out, std::string& error);
// Writes atomically (temporary file in the same folder, then rename); false with `error`.
bool write_stroke_file(const std::string& path, const std::vector<StrokeSample>& samples,
                       std::string& error);

}  // namespace ardcell
