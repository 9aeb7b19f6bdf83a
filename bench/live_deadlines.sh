#!/usr/bin/env bash
# Deadline statistics of the live loop: runs `ardcell live` on each preset, resized to SIZE^2,
# for FRAMES frames at a 60 Hz target in an Xvfb window (no vsync, so the frame clock alone
# paces it), and prints the loop's closing lines: frames, deadline misses, work and interval
# percentiles, and the mean/max time of each stage.
#
#   bench/live_deadlines.sh [PRESET...]     (default: cavity-gray-scott space-cookie-5)
#   env: SIZE (512), FRAMES (600), FPS (60), ARDCELL (build/release/ardcell), EXTRA (more flags),
#        REALTIME=1: `--realtime-solvers` (every solve fixed Jacobi sweeps, the reaction
#        tabulated) instead of the presets' multigrid and ICCG
set -euo pipefail
cd "$(dirname "$0")/.."
size=${SIZE:-512}
frames=${FRAMES:-600}
fps=${FPS:-60}
ardcell=${ARDCELL:-build/release/ardcell}
[ -x "$ardcell" ] || { echo "live_deadlines.sh: no $ardcell (build it: scripts/dev.sh run)" >&2; exit 2; }
command -v xvfb-run >/dev/null || { echo "live_deadlines.sh: xvfb-run not found (apt-get install xvfb)" >&2; exit 2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
presets=("$@")
[ ${#presets[@]} -gt 0 ] || presets=(cavity-gray-scott space-cookie-5)
for p in "${presets[@]}"; do
  src=presets/$p.toml
  [ -f "$src" ] || { echo "live_deadlines.sh: no preset $src" >&2; exit 2; }
  sed "s/^size = \[.*\]/size = [$size, $size]/" "$src" > "$tmp/$p.toml"
  echo "== $p at ${size}x${size}, $frames frames, ${fps} Hz target"
  xvfb-run -a -s "-screen 0 1280x1024x24" "$ardcell" live "$tmp/$p.toml" --frames "$frames" \
    --fps "$fps" --no-vsync --scale 1 $([ "${REALTIME:-0}" = 1 ] && echo --realtime-solvers) \
    ${EXTRA:-} 2>&1 | grep -E "^(frames|stages|ardcell live: backend)"
done
