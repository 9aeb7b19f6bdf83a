#!/usr/bin/env bash
# Regenerates every image the docs show (docs/gallery/*.png) with the real ardcell binary:
#   scripts/make_figures.sh            the gallery, into docs/gallery/ (minutes: Fig. 3 runs
#                                      3200 frames at 256^2)
#   scripts/make_figures.sh --small    every command at 64x64 (obstacles 32x64) and 4 frames,
#                                      into a temporary folder that is removed (a smoke test, CI)
# Options: --out DIR (keep the images there), --only GLOB (the images whose name matches, e.g.
# 'fig4*'), ARDCELL=path/to/ardcell (default
# build/release/ardcell; build it with `cmake --build build/release --target ardcell`).
# Every run uses --backend serial, so the images are the same bits on any machine and load.
set -euo pipefail
cd "$(dirname "$0")/.."

small=0
out=""
only="*"
while [ $# -gt 0 ]; do
  case "$1" in
    --small) small=1 ;;
    --out) out=$2; shift ;;
    --only) only=$2; shift ;;
    *) echo "make_figures.sh: unknown argument '$1' (expected --small, --out DIR, --only GLOB)" >&2
       exit 2 ;;
  esac
  shift
done

bin=${ARDCELL:-build/release/ardcell}
if [ ! -x "$bin" ]; then
  echo "make_figures.sh: no ardcell binary at $bin (build it: cmake --build build/release" \
       "--target ardcell, or set ARDCELL=path)" >&2
  exit 2
fi
bin=$(realpath "$bin")
repo=$(pwd)

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
if [ -z "$out" ]; then
  if [ $small -eq 1 ]; then out="$work/gallery"; else out=docs/gallery; fi
fi
mkdir -p "$out"
out=$(realpath "$out")
made=()

# fig OUTNAME FRAME -- ardcell run ARGS...: runs the command (with --size/--steps replaced in
# --small mode), then copies frame FRAME (the last one in --small mode) to OUT/OUTNAME.png.
fig() {
  local name=$1 frame=$2
  shift 3
  # shellcheck disable=SC2053
  [[ $name == $only ]] || return 0
  local args=("$@") dir="$work/run-$name"
  if [ $small -eq 1 ]; then
    local i
    for i in "${!args[@]}"; do
      case "${args[$i]}" in
        --size) case "${args[$((i + 1))]}" in *x*) args[$((i + 1))]=32x64 ;; *) args[$((i + 1))]=64 ;; esac ;;
        --steps) args[$((i + 1))]=4 ;;
        --every) args[$((i + 1))]=4 ;;
      esac
    done
    frame=4
  fi
  (cd "$repo" && "$bin" "${args[@]}" --out "$dir" --quiet --backend serial >/dev/null)
  local file
  file=$(ls "$dir"/*_"$(printf %08d "$frame")".png 2>/dev/null | head -n 1)
  if [ -z "$file" ]; then
    echo "make_figures.sh: $name: frame $frame not written by: ardcell ${args[*]}" >&2
    exit 1
  fi
  cp "$file" "$out/$name.png"
  made+=("$name.png")
}

spiral=presets/strokes/fig3_spiral.jsonl
# Fig. 3: the spiral stroke, deposit only (top) and with the theta0 coupling (bottom).
fig fig3_deposit 3000 -- run fig3-deposit --size 256 --strokes $spiral --paint-radius 8 --steps 3000 --every 200
fig fig3_orient 200 -- run fig3-orient --size 256 --strokes $spiral --paint-radius 12 --steps 3200 --every 200
if [[ fig3_orient == $only ]]; then
  cp "$work/run-fig3_orient/"*_"$( [ $small -eq 1 ] && echo 00000004 || echo 00003200)".png \
    "$out/fig3_orient_3200.png"
  made+=(fig3_orient_3200.png)
fi
# Fig. 4: space cookies with 3, 4, 5 and 8 lobes at the presets' own size and last frame.
for j in 3 4 5 8; do
  fig "fig4_space_cookie_$j" 200 -- run "space-cookie-$j" --size 128 --steps 200 --every 200
done
# Fig. 5: the lid-driven cavity, advection only and with three reaction models.
for m in advect gray-scott fhn barkley; do
  fig "fig5_cavity_$m" 1500 -- run "cavity-$m" --size 128 --steps 1500 --every 1500
done
# Fig. 6: flow past an obstacle, advection only and advection-reaction-diffusion.
for m in advect ard-gray-scott ard-fhn ard-barkley; do
  fig "fig6_obstacle_$m" 1500 -- run "obstacle-$m" --size 96x192 --steps 1500 --every 1500
done
# Seed 003: generalized (non-Gaussian) diffusion textures, Turing and Gray-Scott, Table 2's (a),
# (d) (axes) and (e) (diagonals).
for q in turing-a turing-d turing-e gray-scott-d gray-scott-e; do
  fig "seed003_$q" 400 -- run "mcgraw-$q" --size 128 --steps 400 --every 400
done
# Seed 003, Fig. 6: Gray-Scott's F/k parameter map with sequence (e).
fig seed003_gray-scott-map 1000 -- run mcgraw-gray-scott-map --size 256 --steps 1000 --every 1000
# Seed 003, Fig. 1: the propagators of sequences (c), (d) and (e) (no simulation).
for q in c d e; do
  name="seed003_propagator_$q"
  # shellcheck disable=SC2053
  [[ $name == $only ]] || continue
  size=256
  [ $small -eq 1 ] && size=64
  (cd "$repo" && "$bin" propagator "$q" --size "$size" --out "$out/$name.png" >/dev/null)
  made+=("$name.png")
done
# Seed 004: Gray-Scott on the Catmull-Clark limit surface of the double torus (no frames: a
# render from a fixed camera).
name=surface_genus2
# shellcheck disable=SC2053
if [[ $name == $only ]]; then
  cells=16 steps=3000
  [ $small -eq 1 ] && cells=4 steps=4
  (cd "$repo" && "$bin" surface --shape genus2 --patch-cells "$cells" --steps "$steps" \
    --render "$out/$name.png" --view 30,40 >/dev/null)
  made+=("$name.png")
fi
# The DFG cylinder benchmark 2D-2 (Re 100): the vortex street behind the cylinder, by its dye.
fig dfg_2d2 1600 -- run dfg-2d2 --size 440x82 --steps 1600 --every 1600
# The plain cavity's dye.
fig cavity 1000 -- run cavity --size 128 --steps 1000 --every 1000

# The live window, painted by the attract mode replaying the spiral.
live_frames=150
[ $small -eq 1 ] && live_frames=4
live=("$bin" live ink --frames "$live_frames" --hud --attract 0 --attract-dir presets/strokes
      --backend serial --no-vsync --scale 2 --screenshot "$out/live.png")
if [[ live != $only ]]; then
  :
elif [ -n "${DISPLAY:-}" ]; then
  "${live[@]}" >/dev/null 2>&1
  made+=(live.png)
elif command -v xvfb-run >/dev/null; then
  xvfb-run -a -s "-screen 0 800x600x24" "${live[@]}" >/dev/null 2>&1
  made+=(live.png)
else
  echo "make_figures.sh: no X display and no xvfb-run: live.png not made" >&2
fi

for f in "${made[@]}"; do
  [ -s "$out/$f" ] || { echo "make_figures.sh: $out/$f is missing or empty" >&2; exit 1; }
done
echo "make_figures.sh: ${#made[@]} images in $out"
