#!/usr/bin/env python3
"""Writes presets/strokes/fig3_spiral.jsonl: the single spiral stroke of Kim & Lin's Fig. 3.

An Archimedean spiral r = r0 + (r1 - r0) * s, angle = 2.5 turns * s (s in [0, 1]) around the
canvas centre, drawn from the inside out in 2 seconds at 200 samples/s with pressure 0.8, then
one pen-up sample. Coordinates are normalized (x right, y down), as in host/paint/stroke_io.h.
Run: scripts/make_fig3_spiral.py [OUT]
"""
import json
import math
import sys

out = sys.argv[1] if len(sys.argv) > 1 else "presets/strokes/fig3_spiral.jsonl"
rate, seconds, turns, r0, r1 = 200, 2.0, 2.5, 0.04, 0.36
n = int(rate * seconds)
lines = []
for i in range(n + 1):
    s = i / n
    a = 2 * math.pi * turns * s
    r = r0 + (r1 - r0) * s
    sample = {"t": round(i / rate, 6), "x": round(0.5 + r * math.cos(a), 6),
              "y": round(0.5 + r * math.sin(a), 6), "pressure": 0.8, "tilt_x": 0, "tilt_y": 0,
              "buttons": 1, "in_range": True, "eraser": False}
    lines.append(json.dumps(sample))
last = json.loads(lines[-1])
last.update({"t": round((n + 1) / rate, 6), "pressure": 0.0, "buttons": 0})
lines.append(json.dumps(last))
tmp = out + ".tmp"
with open(tmp, "w") as f:
    f.write("\n".join(lines) + "\n")
import os
os.replace(tmp, out)
