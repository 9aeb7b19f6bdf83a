#!/usr/bin/env bash
# Writes docs/presets.md, the preset key reference, from the key table that validates presets
# (host/scenes/preset.cpp) as the binary prints it: `ardcell live --keys --markdown`.
# live_cli_test fails while docs/presets.md differs from that output.
#   scripts/preset_keys.sh [PATH_TO_ARDCELL]   (default: build/*/ardcell, the newest)
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-$(ls -t build/*/ardcell 2>/dev/null | head -n 1)}
if [ -z "$bin" ] || [ ! -x "$bin" ]; then
  echo "preset_keys.sh: no ardcell binary (build one, or pass its path)" >&2
  exit 2
fi
tmp=$(mktemp docs/.presets.md.XXXXXX)
trap 'rm -f "$tmp"' EXIT
"$bin" live --keys --markdown >"$tmp"
chmod 644 "$tmp"
mv "$tmp" docs/presets.md
trap - EXIT
echo "preset_keys.sh: wrote docs/presets.md with $bin"
