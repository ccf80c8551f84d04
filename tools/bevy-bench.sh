#!/usr/bin/env bash
# Frame times of the Bevy plugin (integrations/bevy_pelt's render example, Bevy 0.19 on
# lavapipe) beside pelt's forward mode (lavapipe), alternated in rounds so that the machine's
# drift falls on both: the demo Fox at Walk 0.35 s (springs removed) with 16 shells, the same
# scene without its fur (the Fox drawn opaque: the fur's cost), and Bevy drawing no object at
# all (its own overhead: ECS, render graph, clustering, the sky). Needs `pelt demo` run in
# OUT_DEMO, pelt's release build and the plugin's:
#   cargo build --release
#   cargo build --release --manifest-path integrations/bevy_pelt/Cargo.toml --examples
#   bash tools/bevy-bench.sh out/demo 1280x720 10 3
set -euo pipefail
demo=${1:-out/demo}
size=${2:-1280x720}
frames=${3:-10}
rounds=${4:-3}
root=$(cd "$(dirname "$0")/.." && pwd)
pelt="$root/target/release/pelt"
bevy="$root/integrations/bevy_pelt/target/release/examples/render"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$demo"
python3 - "$work" <<'PY'
import json, sys
work = sys.argv[1]
f = json.load(open('fox.json'))
for o in f['objects']:
    o.get('material', {}).pop('spring', None)
json.dump(f, open(f'{work}/fox.json', 'w'))
bare = json.loads(json.dumps(f))
bare['objects'][0]['material'] = {'kind': 'opaque'}
json.dump(bare, open(f'{work}/bare.json', 'w'))
empty = json.loads(json.dumps(f))
empty['objects'] = []
json.dump(empty, open(f'{work}/empty.json', 'w'))
PY
for a in fox.glb; do cp "$a" "$work/"; done
cd "$work"
args=(--shells 16 --animation Walk --time 0.35 --size "$size" --bench "$frames")
pelt_ms() { "$pelt" render "$1" --mode forward --backend vulkan "${args[@]}" --json -q -o p.png | python3 -c 'import json,sys; t=sorted(f["ms"] for f in json.load(sys.stdin)["frames"][1:]); print(f"{t[len(t)//2]:.0f}")'; }
bevy_ms() { WGPU_BACKEND=vulkan "$bevy" "$1" "${args[@]}" -o b.png 2>/dev/null | python3 -c 'import json,sys; print("%.0f" % json.load(sys.stdin)["medianMs"])'; }
declare -A sum
for r in $(seq "$rounds"); do
  line="round $r:"
  for k in pelt:fox.json bevy:fox.json pelt:bare.json bevy:bare.json bevy:empty.json; do
    tool=${k%%:*}; scene=${k#*:}
    ms=$("${tool}_ms" "$scene")
    line="$line $k=$ms"
    sum[$k]="${sum[$k]:-} $ms"
  done
  echo "$line" >&2
done
med() { python3 -c 'import sys; v=sorted(float(x) for x in sys.argv[1:]); print("%.0f" % v[len(v)//2])' $1; }
echo "| $size, 16 shells, median of $rounds rounds × $frames frames | pelt forward (ms) | Bevy + bevy_pelt (ms) |"
echo "|---|---|---|"
echo "| Fox with fur | $(med "${sum[pelt:fox.json]}") | $(med "${sum[bevy:fox.json]}") |"
echo "| Fox without fur (drawn opaque) | $(med "${sum[pelt:bare.json]}") | $(med "${sum[bevy:bare.json]}") |"
echo "| no object (Bevy's own overhead) | – | $(med "${sum[bevy:empty.json]}") |"
