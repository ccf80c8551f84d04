#!/usr/bin/env bash
# The strand reference's time on small and extreme inputs (160x90, the fixture sphere's fur):
# the sphere filling the frame, 10 pixels across, 1e-4 m (lit alike, and under the 1 m scene's
# light, 20 times brighter), very thin strands, and fur 100 times longer than the sphere's.
# Prints one row per case: strands, grid, samples, frames, seconds.
# Usage: bash bench/strands.sh [PELT]   (default target/release/pelt)
set -euo pipefail
cd "$(dirname "$0")/.."
pelt=${1:-target/release/pelt}
[ -x "$pelt" ] || cargo build --release
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
# The sphere furred by the example config, and again with strands a fifth as wide.
"$pelt" bake -q fixtures/sphere.glb -o "$dir/sphere.glb" --config fixtures/fur.json
python3 -c 'import json, sys; c = json.load(open(sys.argv[1])); c["fur"]["textures"]["radius"] /= 5; print(json.dumps(c))' \
  fixtures/fur.json >"$dir/thin.json"
"$pelt" bake -q fixtures/sphere.glb -o "$dir/thin.glb" --config "$dir/thin.json"
scene() { # name asset scale camera-distance light-intensity length
  python3 - "$@" <<'PY'
import json, sys
name, asset, s, dist, power, length = sys.argv[1:]
s, dist, power = float(s), float(dist), float(power)
fur = {"kind": "fur"} if length == "-" else {"kind": "fur", "length": float(length)}
print(json.dumps({
    "output": {"width": 160, "height": 90},
    "camera": {"position": [0, 1.4 * s, dist * s], "target": [0, 0.5 * s, 0], "fovYDeg": 40,
               "near": 0.2 * s, "far": (dist + 20) * s},
    "ambient": [0.05, 0.05, 0.05],
    "objects": [{"asset": asset, "transform": {"scale": [s, s, s]}, "material": fur}],
    "lights": [{"position": [2 * s, 3 * s, 3 * s], "color": [1, 1, 1], "intensity": power,
                "radius": 100 * s}],
}))
PY
}
scene unit sphere.glb 1 3.2 0.7 - >"$dir/unit.json"
scene far sphere.glb 1 40 60 - >"$dir/far.json"
scene tiny-alike sphere.glb 1e-4 3.2 0.0345 - >"$dir/tiny-alike.json"
scene tiny-bright sphere.glb 1e-4 3.2 0.7 - >"$dir/tiny-bright.json"
scene thin thin.glb 1 3.2 0.7 - >"$dir/thin.json"
scene long sphere.glb 1 3.2 0.7 4 >"$dir/long.json"
echo "| case | strands | grid | samples per pixel | frames | seconds |"
echo "|---|---|---|---|---|---|"
for c in unit far tiny-alike tiny-bright thin long; do
  start=$(date +%s.%N)
  line=$("$pelt" render "$dir/$c.json" -o "$dir/$c.png" --mode strands 2>&1 | grep "^wrote")
  end=$(date +%s.%N)
  python3 - "$c" "$line" "$start" "$end" <<'PY'
import re, sys
c, line, start, end = sys.argv[1:]
m = re.search(r"(\d+) strands, (\d+) samples per pixel in (\d+) frames of (\d+)", line)
if not m:
    sys.exit(f"| {c} | did not finish | | | | {float(end) - float(start):.1f} |")
print(f"| {c} | {m[1]} | {m[4]}×{m[4]} | {m[2]} | {m[3]} | {float(end) - float(start):.1f} |")
PY
done
